#include "tools/output/run_checkpoint.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <tuple>

#include "core/input_limits.h"
#include "core/mesh.h"

namespace jetshell {
namespace {

using Json = nlohmann::json;

/// Counts a run adds up (Newton iterations, cuts, safeguards): far beyond any run's, far below int's overflow.
constexpr std::int64_t kMaxCount = 1'000'000'000;
/// File sizes of frames.pvd and probes.csv (the files are checked against them when reopened).
constexpr std::int64_t kMaxOutputBytes = std::int64_t{1} << 50;

/// Builds the document of a CBOR stream as nlohmann's own DOM builder does, but refuses nesting deeper than the
/// scene reader allows: the CBOR parser recurses once per level, and 2 MB of nested arrays overflowed the stack.
class BoundedDepthCbor final : public nlohmann::json_sax<Json> {
 public:
  BoundedDepthCbor(Json& result, int maxDepth) : dom_(result, false), maxDepth_(maxDepth) {}
  bool null() override { return dom_.null(); }
  bool boolean(bool v) override { return dom_.boolean(v); }
  bool number_integer(number_integer_t v) override { return dom_.number_integer(v); }
  bool number_unsigned(number_unsigned_t v) override { return dom_.number_unsigned(v); }
  bool number_float(number_float_t v, const string_t& text) override { return dom_.number_float(v, text); }
  bool string(string_t& v) override { return dom_.string(v); }
  bool binary(binary_t& v) override { return dom_.binary(v); }
  bool start_object(std::size_t n) override { return ++depth_ <= maxDepth_ && dom_.start_object(n); }
  bool key(string_t& v) override { return dom_.key(v); }
  bool end_object() override {
    --depth_;
    return dom_.end_object();
  }
  bool start_array(std::size_t n) override { return ++depth_ <= maxDepth_ && dom_.start_array(n); }
  bool end_array() override {
    --depth_;
    return dom_.end_array();
  }
  bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception&) override { return false; }

 private:
  nlohmann::detail::json_sax_dom_parser<Json> dom_;
  int depth_ = 0;
  const int maxDepth_;
};

/// Reads the fields of one object of the checkpoint; every message names the file and the field's path.
class Fields {
 public:
  Fields(const Json& j, std::string file, std::string path) : j_(j), file_(std::move(file)), path_(std::move(path)) {
    if (!j_.is_object()) fail("", "must be an object");
  }
  [[noreturn]] void fail(const std::string& key, const std::string& rule) const {
    throw InputError(file_ + ": " + name(key) + ": " + rule);
  }
  std::string name(const std::string& key) const {
    return path_.empty() ? key : key.empty() ? path_ : path_ + "/" + key;
  }
  bool has(const std::string& key) const { return j_.contains(key); }
  const Json& at(const std::string& key) const {
    const auto it = j_.find(key);
    if (it == j_.end()) fail(key, "missing (an incomplete checkpoint)");
    return *it;
  }
  Fields object(const std::string& key) const { return Fields(at(key), file_, name(key)); }
  /// An entry of one of this object's lists, named `path` below it.
  Fields element(const Json& v, const std::string& path) const { return Fields(v, file_, name(path)); }

  std::int64_t integer(const std::string& key, std::int64_t lo, std::int64_t hi) const {
    return integerValue(at(key), key, lo, hi);
  }
  int count(const std::string& key, std::int64_t hi = kMaxCount) const { return static_cast<int>(integer(key, 0, hi)); }
  double number(const std::string& key, double lo, double hi, const std::string& rule) const {
    const Json& v = at(key);
    if (!v.is_number()) fail(key, "must be a number");
    const double d = v.get<double>();
    if (!std::isfinite(d) || d < lo || d > hi) fail(key, rule);
    return d;
  }
  bool boolean(const std::string& key) const {
    const Json& v = at(key);
    if (!v.is_boolean()) fail(key, "must be true or false");
    return v.get<bool>();
  }
  const Json& array(const std::string& key, std::size_t maxSize) const {
    const Json& v = at(key);
    if (!v.is_array()) fail(key, "must be a list");
    if (v.size() > maxSize)
      fail(key, "holds " + std::to_string(v.size()) + " entries (at most " + std::to_string(maxSize) + ")");
    return v;
  }
  /// A list of exactly `size` finite numbers.
  std::vector<double> finiteList(const Json& v, const std::string& key, std::size_t size) const {
    if (!v.is_array() || v.size() != size) fail(key, "must be a list of " + std::to_string(size) + " numbers");
    std::vector<double> out(size);
    for (std::size_t k = 0; k < size; ++k) {
      if (!v[k].is_number() || !std::isfinite(v[k].get<double>()))
        fail(key, "holds a value that is not a finite number");
      out[k] = v[k].get<double>();
    }
    return out;
  }
  /// `size` finite numbers packed as one byte string (packedJson): the plot rows' lists, the bulk of a long run's
  /// checkpoint, which as lists of CBOR numbers cost a document node each to write and to read.
  std::vector<double> packedList(const std::string& key, std::size_t size) const {
    const Json& v = at(key);
    if (!v.is_binary() || v.get_binary().size() != 8 * size)
      fail(key, "must be " + std::to_string(size) + " numbers packed as a byte string of " +
                    std::to_string(8 * size) + " bytes (little-endian doubles)");
    const std::vector<std::uint8_t>& bytes = v.get_binary();
    std::vector<double> out(size);
    for (std::size_t k = 0; k < size; ++k) {
      std::uint64_t word = 0;
      for (int b = 7; b >= 0; --b) word = (word << 8) | bytes[8 * k + static_cast<std::size_t>(b)];
      std::memcpy(&out[k], &word, sizeof word);
      if (!std::isfinite(out[k])) fail(key, "holds a value that is not a finite number");
    }
    return out;
  }
  Eigen::VectorXd vector(const std::string& key, std::size_t size) const {
    const std::vector<double> values = finiteList(at(key), key, size);
    return Eigen::Map<const Eigen::VectorXd>(values.data(), static_cast<Eigen::Index>(size));
  }
  std::int64_t integerValue(const Json& v, const std::string& key, std::int64_t lo, std::int64_t hi) const {
    const std::string rule = "must be a whole number in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
    // Only integers: a float (1e300) or an unsigned beyond int64 would be cut or wrap when converted.
    if (v.is_number_unsigned()) {
      if (v.get<std::uint64_t>() > static_cast<std::uint64_t>(hi)) fail(key, rule);
    } else if (!v.is_number_integer()) {
      fail(key, rule);
    }
    const std::int64_t n =
        v.is_number_unsigned() ? static_cast<std::int64_t>(v.get<std::uint64_t>()) : v.get<std::int64_t>();
    if (n < lo || n > hi) fail(key, rule);
    return n;
  }

 private:
  const Json& j_;
  std::string file_, path_;
};

SolverCheckpoint solverFrom(const Fields& f, const CheckpointScene& scene) {
  SolverCheckpoint s;
  const std::size_t n = 3 * static_cast<std::size_t>(scene.vertices);
  s.steps = f.count("steps", scene.maxSteps);
  s.t = f.number("t", 0.0, scene.duration * (1.0 + 1e-9), "must lie in [0, duration]");
  s.historyStep = f.number("history_step", 0.0, std::numeric_limits<double>::max(), "must be finite and >= 0");
  s.historyValid = f.boolean("history_valid");
  s.x = f.vector("x", n);
  s.v = f.vector("v", n);
  // The previous step's state matters only with a valid history; without one the solver may hold none.
  for (const auto& [key, previous] : {std::pair{"x_prev", &s.xPrev}, std::pair{"v_prev", &s.vPrev}}) {
    const Json& v = f.at(key);
    const bool empty = v.is_array() && v.empty() && !s.historyValid;
    *previous = empty ? Eigen::VectorXd() : f.vector(key, n);
  }
  return s;
}

SafeguardCounts safeguardsFrom(const Fields& f, const CheckpointScene& scene) {
  SafeguardCounts s;
  const Json& cuts = f.at("cuts");
  if (!cuts.is_object() || cuts.size() > scene.cutReasons.size())
    f.fail("cuts", "must be an object of at most " + std::to_string(scene.cutReasons.size()) + " counts by reason");
  const Fields byReason = f.object("cuts");
  for (const auto& item : cuts.items()) {
    if (std::find(scene.cutReasons.begin(), scene.cutReasons.end(), item.key()) == scene.cutReasons.end()) {
      std::string list;
      for (const std::string& r : scene.cutReasons) list += (list.empty() ? "" : ", ") + r;
      f.fail("cuts", "a reason must be one of the reasons a step is cut for (" + list + ")");
    }
    s.cuts[item.key()] = byReason.count(item.key());
  }
  s.nonFiniteTrials = f.count("non_finite_trials");
  s.regularizedSolves = f.count("regularized_solves");
  s.regularizations = f.count("regularizations");
  s.projectionFallbacks = f.count("projection_fallbacks");
  s.acceptedAtCap = f.count("accepted_at_cap");
  s.solvedAgain = f.has("solved_again") ? f.count("solved_again") : 0;              // absent before it was counted
  s.directFallbacks = f.has("direct_fallbacks") ? f.count("direct_fallbacks") : 0;  // likewise
  s.largestShift = f.number("largest_shift", 0.0, std::numeric_limits<double>::max(), "must be finite and >= 0");
  return s;
}

/// A frame file's name as RunOutput writes it: frames/ then letters, digits and '_', then .vtu. Nothing else may
/// be read back as the last frame (a path outside the output directory, a device).
bool isFrameFileName(const std::string& name) {
  const std::string prefix = "frames/", suffix = ".vtu";
  if (name.size() <= prefix.size() + suffix.size() || name.size() > 128 ||
      name.compare(0, prefix.size(), prefix) != 0 ||
      name.compare(name.size() - suffix.size(), suffix.size(), suffix) != 0)
    return false;
  for (std::size_t k = prefix.size(); k < name.size() - suffix.size(); ++k) {
    const char c = name[k];
    if (!((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_')) return false;
  }
  return true;
}

/// Doubles as one CBOR byte string, 8 little-endian bytes each (Fields::packedList reads it).
Json packedJson(const std::vector<double>& values) {
  std::vector<std::uint8_t> bytes(8 * values.size());
  for (std::size_t k = 0; k < values.size(); ++k) {
    std::uint64_t word = 0;
    std::memcpy(&word, &values[k], sizeof word);
    for (std::size_t b = 0; b < 8; ++b) bytes[8 * k + b] = static_cast<std::uint8_t>(word >> (8 * b));
  }
  return Json::binary(std::move(bytes));
}

/// A probe row: u and force as lists of numbers (the last row), or packed (the plot rows).
ProbeRow rowFrom(const Fields& row, const CheckpointScene& scene, int steps, bool packed) {
  ProbeRow r;
  r.step = static_cast<int>(row.integer("step", 0, steps));
  r.time = row.number("time", 0.0, scene.duration * (1.0 + 1e-9), "must lie in [0, duration]");
  r.loadFactor = row.number("load_factor", -std::numeric_limits<double>::max(), std::numeric_limits<double>::max(),
                            "must be finite");
  const std::size_t uSize = 3 * static_cast<std::size_t>(scene.probes);
  const std::size_t forceSize = 3 * static_cast<std::size_t>(scene.contactSolids);
  r.u = packed ? row.packedList("u", uSize) : row.finiteList(row.at("u"), "u", uSize);
  r.force = packed ? row.packedList("force", forceSize) : row.finiteList(row.at("force"), "force", forceSize);
  return r;
}

OutputCheckpoint outputFrom(const Fields& f, const CheckpointScene& scene, int steps) {
  OutputCheckpoint o;
  o.frames = f.count("frames", steps + 1);
  // Written after a step: the initial state's row at least.
  o.lastRow = rowFrom(f.object("last_row"), scene, steps, false);
  const int lastStep = o.lastRow->step;
  o.lastFrameStep = static_cast<int>(f.integer("last_frame_step", -1, lastStep));
  const Json& last = f.array("last_frame", static_cast<std::size_t>(scene.frameFiles));
  if (!last.empty() && last.size() != static_cast<std::size_t>(scene.frameFiles))
    f.fail("last_frame", "must name " + std::to_string(scene.frameFiles) + " frame file(s), or none");
  for (const Json& name : last) {
    if (!name.is_string() || !isFrameFileName(name.get<std::string>()))
      f.fail("last_frame", "must name files frames/NAME.vtu (letters, digits and _) inside the output directory");
    o.lastFrame.push_back(name.get<std::string>());
  }
  PlotRows& plot = o.plotRows;
  plot.capacity = PlotRows::capacityFor(3 + 3 * static_cast<std::size_t>(scene.probes) +
                                        3 * static_cast<std::size_t>(scene.contactSolids));
  const Json& rows = f.array("plot_rows", plot.capacity);
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const std::string where = "plot_rows/" + std::to_string(k);
    const Fields row = f.element(rows[k], where);
    plot.rows.push_back(rowFrom(row, scene, steps, true));
    if (plot.rows.back().step > lastStep || (k > 0 && plot.rows.back().step <= plot.rows[k - 1].step))
      f.fail(where + "/step", "must increase row by row up to the last row's");
    RowRange& range = plot.ranges.emplace_back();
    const std::size_t uSize = plot.rows.back().u.size(), forceSize = plot.rows.back().force.size();
    for (const auto& [key, values, size] :
         {std::tuple{"u_low", &range.uLow, uSize}, std::tuple{"u_high", &range.uHigh, uSize},
          std::tuple{"force_low", &range.forceLow, forceSize}, std::tuple{"force_high", &range.forceHigh, forceSize}}) {
      *values = row.packedList(key, size);
    }
    if (!range.holds(plot.rows.back()))
      f.fail(where, "u_low <= u <= u_high and force_low <= force <= force_high must hold value by value");
  }
  plot.stride = f.integer("plot_stride", 1, std::int64_t{1} << 40);
  plot.recorded = f.integer("recorded_rows", 0, static_cast<std::int64_t>(steps) + 1);
  if (!plot.consistent() || plot.recorded == 0)
    f.fail("plot_rows", "do not match plot_stride and recorded_rows (every stride-th of the recorded rows, at most " +
                            std::to_string(plot.capacity) + ", the stride a power of two, the last row recorded)");
  for (const auto& [key, bytes] : {std::pair{"pvd_bytes", &o.pvdBytes}, std::pair{"probes_bytes", &o.probesBytes}})
    if (!f.at(key).is_null()) *bytes = static_cast<std::uint64_t>(f.integer(key, 0, kMaxOutputBytes));
  o.lastRowOffset = static_cast<std::uint64_t>(
      f.integer("last_row_offset", 0, o.probesBytes ? static_cast<std::int64_t>(*o.probesBytes) : 0));
  return o;
}

Json vectorJson(const Eigen::VectorXd& v) { return std::vector<double>(v.data(), v.data() + v.size()); }

}  // namespace

Json toJson(const RunCheckpoint& c, const CheckpointScene& scene) {
  const SolverCheckpoint& s = c.solver;
  const SafeguardCounts& g = c.safeguards;
  const OutputCheckpoint& o = c.output;
  const auto rowJson = [](const ProbeRow& r) {
    return Json{{"step", r.step}, {"time", r.time}, {"load_factor", r.loadFactor}, {"u", r.u}, {"force", r.force}};
  };
  Json plotRows = Json::array();
  for (std::size_t k = 0; k < o.plotRows.rows.size() && k < o.plotRows.ranges.size(); ++k) {
    const ProbeRow& r = o.plotRows.rows[k];
    const RowRange& range = o.plotRows.ranges[k];
    plotRows.push_back(Json{{"step", r.step},
                            {"time", r.time},
                            {"load_factor", r.loadFactor},
                            {"u", packedJson(r.u)},
                            {"force", packedJson(r.force)},
                            {"u_low", packedJson(range.uLow)},
                            {"u_high", packedJson(range.uHigh)},
                            {"force_low", packedJson(range.forceLow)},
                            {"force_high", packedJson(range.forceHigh)}});
  }
  const auto bytes = [](const std::optional<std::uint64_t>& n) { return n ? Json(*n) : Json(nullptr); };
  return {{"scene_fingerprint", scene.fingerprint},
          {"vertices", scene.vertices},
          {"time_step", scene.timeStep},
          {"solver",
           {{"x", vectorJson(s.x)},
            {"v", vectorJson(s.v)},
            {"x_prev", vectorJson(s.xPrev)},
            {"v_prev", vectorJson(s.vPrev)},
            {"t", s.t},
            {"history_step", s.historyStep},
            {"steps", s.steps},
            {"history_valid", s.historyValid}}},
          {"checkpoint_every", c.checkpointEvery},
          {"newton_iterations", c.newtonIterations},
          {"cuts", c.cuts},
          {"steps_at_iteration_cap", c.stepsAtIterationCap},
          {"worst_residual_over_tolerance", c.worstResidualOverTolerance},
          {"safeguards",
           {{"cuts", g.cuts},
            {"non_finite_trials", g.nonFiniteTrials},
            {"regularized_solves", g.regularizedSolves},
            {"regularizations", g.regularizations},
            {"projection_fallbacks", g.projectionFallbacks},
            {"accepted_at_cap", g.acceptedAtCap},
            {"largest_shift", g.largestShift},
            {"solved_again", g.solvedAgain},
            {"direct_fallbacks", g.directFallbacks}}},
          {"output",
           {{"frames", o.frames},
            {"last_frame_step", o.lastFrameStep},
            {"last_frame", o.lastFrame},
            {"last_row", o.lastRow ? rowJson(*o.lastRow) : Json(nullptr)},
            {"plot_rows", plotRows},
            {"plot_stride", o.plotRows.stride},
            {"recorded_rows", o.plotRows.recorded},
            {"pvd_bytes", bytes(o.pvdBytes)},
            {"probes_bytes", bytes(o.probesBytes)},
            {"last_row_offset", o.lastRowOffset}}}};
}

RunCheckpoint runCheckpointFromJson(const Json& j, const CheckpointScene& scene, const std::string& file) {
  const Fields f(j, file, "");
  // Written for this scene: the same file text, size and time step (exactly: doubles survive CBOR).
  const bool same = f.has("scene_fingerprint") && f.at("scene_fingerprint") == scene.fingerprint && f.has("vertices") &&
                    f.at("vertices") == scene.vertices && f.has("time_step") && f.at("time_step") == scene.timeStep;
  if (!same) throw InputError(file + ": written for another scene (or the scene file changed since)");
  RunCheckpoint c;
  c.solver = solverFrom(f.object("solver"), scene);
  const int steps = c.solver.steps;
  c.checkpointEvery = static_cast<int>(f.integer("checkpoint_every", 1, std::max(1, scene.maxSteps)));
  c.newtonIterations = f.count("newton_iterations");
  c.cuts = f.count("cuts");
  c.stepsAtIterationCap = f.count("steps_at_iteration_cap", steps);
  c.worstResidualOverTolerance =
      f.number("worst_residual_over_tolerance", 0.0, std::numeric_limits<double>::max(), "must be finite and >= 0");
  c.safeguards = safeguardsFrom(f.object("safeguards"), scene);
  c.output = outputFrom(f.object("output"), scene, steps);
  return c;
}

Json parseCheckpoint(const std::string& bytes, const std::string& file) {
  Json j;
  BoundedDepthCbor builder(j, inputLimits().maxJsonDepth);
  bool parsed = false;
  try {
    parsed = Json::sax_parse(bytes, &builder, Json::input_format_t::cbor, true);
  } catch (const Json::exception&) {  // a declared length beyond any container's size
  }
  if (!parsed || !j.is_object() || !j.contains(kCheckpointVersionKey))
    throw InputError(file + ": not a jetshell checkpoint");
  const Json& version = j.at(kCheckpointVersionKey);
  if (version != kCheckpointVersion)
    throw InputError(file + ": checkpoint version " +
                     (version.is_number_integer() ? version.dump() : "(not a number)") + " (this build reads " +
                     std::to_string(kCheckpointVersion) + ")");
  return j;
}

}  // namespace jetshell
