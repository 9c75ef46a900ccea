#include "tools/output/run_output.h"

#include "core/mesh_io.h"
#include "tools/output/atomic_file.h"
#include "tools/output/volume_meshes.h"

#include <cstdio>
#include <filesystem>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace jetshell {
namespace {

std::string frameName(int index, const char* extension) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "frame_%05d.%s", index, extension);
  return buffer;
}

/// The moving volume actors' file of a frame, in frames/ (.vtu) or obj/ (.obj).
std::string movingVolumesName(int frame, const char* extension) {
  return "volumes_" + frameName(frame, extension).substr(6);
}

void createDirectory(const std::filesystem::path& p) {
  std::error_code ec;
  std::filesystem::create_directories(p, ec);
  if (ec || !std::filesystem::is_directory(p)) throw InputError(p.string() + ": cannot create the output directory (" + ec.message() + ")");
}

/// frames/ or obj/ inside the output directory, not a link out of it: a link there (an output directory unpacked
/// from elsewhere, resumed) would put the run's files, and replace same-named ones, wherever it points.
void createSubdirectory(const std::filesystem::path& p) {
  std::error_code ec;
  if (std::filesystem::is_symlink(std::filesystem::symlink_status(p, ec)))
    throw InputError(p.string() + ": a symbolic link: a run writes its files only inside its output directory");
  createDirectory(p);
}

/// A CSV field (RFC 4180): quoted when it holds a comma, a quote or a line break, quotes doubled.
std::string csvField(const std::string& text) {
  if (text.find_first_of(",\"\r\n") == std::string::npos) return text;
  std::string out = "\"";
  for (const char c : text) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

/// A row of probes.csv: step, time, load factor, the probes' displacements, the solids' forces.
std::string csvRow(const ProbeRow& r) {
  std::ostringstream out;
  out << r.step << ',' << formatDouble(r.time) << ',' << formatDouble(r.loadFactor);
  for (double u : r.u) out << ',' << formatDouble(u);
  for (double f : r.force) out << ',' << formatDouble(f);
  out << '\n';
  return out.str();
}

}  // namespace

/// The volume actors' surfaces (as placed at t = 0) moved where their paths put them at time t
/// (RigidPath::motion), one mesh, its `volume` cell array the actor's index among the scene's volume actors.
VtuFrame RunOutput::volumesFrame(const std::vector<VolumePart>& parts, double t) {
  VtuFrame frame;
  Eigen::Index nv = 0, nf = 0;
  for (const VolumePart& p : parts) nv += p.surface.V.rows(), nf += p.surface.F.rows();
  frame.points.resize(nv, 3);
  frame.triangles.resize(nf, 3);
  VtuFrame::Array& id = frame.cellData["volume"];
  nv = nf = 0;
  for (const VolumePart& p : parts) {
    const RigidPath::Motion move = p.path.motion(0.0, t);
    for (Eigen::Index v = 0; v < p.surface.V.rows(); ++v)
      frame.points.row(nv + v) = move(p.surface.V.row(v).transpose()).transpose();
    frame.triangles.middleRows(nf, p.surface.F.rows()) = p.surface.F.array() + static_cast<int>(nv);
    id.values.insert(id.values.end(), static_cast<std::size_t>(p.surface.F.rows()), static_cast<double>(p.index));
    nv += p.surface.V.rows();
    nf += p.surface.F.rows();
  }
  return frame;
}

RunOutput::RunOutput(std::string directory, const Scene& scene, const SceneModel& model, std::string scenePath)
    : directory_(std::move(directory)), scenePath_(std::move(scenePath)), scene_(scene), model_(model) {
  namespace fs = std::filesystem;
  createDirectory(directory_);
  if (scene.outputs.vtu) createSubdirectory(fs::path(directory_) / "frames");
  if (scene.outputs.obj) createSubdirectory(fs::path(directory_) / "obj");
  if (!scene.volumes.empty()) {
    const Eigen::Vector3d lo = model.world.V.colwise().minCoeff(), hi = model.world.V.colwise().maxCoeff();
    const double size = std::max(1e-3, 0.8 * (hi - lo).maxCoeff());  // a plane is drawn as a square this half-size
    std::vector<VolumePart> still;
    for (std::size_t k = 0; k < scene.volumes.size(); ++k) {
      // Each on its path as the analysis reads it (a static frame's time is its load factor); those that move
      // go into the frames when frames are written.
      VolumePart part{volumeSurface(scene.volumes[k], size, 0.5 * (lo + hi)), static_cast<int>(k),
                      rigidPath(scene.volumes[k], scene.analysis.type)};
      const bool moves = (scene.outputs.vtu || scene.outputs.obj) && !part.path.isStatic();
      (moves ? movingVolumes_ : still).push_back(std::move(part));
    }
    if (!still.empty()) {
      const VtuFrame frame = volumesFrame(still, 0.0);
      staticVolumesFile_ = (fs::path(directory_) / "volumes.vtu").string();
      writeFileAtomically(staticVolumesFile_, [&](std::ostream& out) { writeVtu(out, frame); });
      if (scene.outputs.obj)
        writeFileAtomically((fs::path(directory_) / "obj" / "volumes.obj").string(),
                            [&](std::ostream& out) { writeObj(out, frame.points, frame.triangles); });
    }
  }
}

void RunOutput::record(const StepState& s, bool forceFrame) {
  const Eigen::VectorXd& x = *s.x;
  ProbeRow row{s.step, s.time, s.loadFactor, {}, {}};
  for (const ResolvedProbe& p : model_.probes)
    for (int c = 0; c < 3; ++c) row.u.push_back(x[3 * p.vertex + c] - model_.world.V(p.vertex, c));
  if (contactForces_) {
    const std::vector<Eigen::Vector3d> forces = contactForces_(x, s.time);
    if (forces.size() != contactSolids_.size())
      throw std::logic_error("RunOutput: the contact force gauge measured " + std::to_string(forces.size()) +
                             " solids, not " + std::to_string(contactSolids_.size()));
    for (const Eigen::Vector3d& f : forces) row.force.insert(row.force.end(), {f.x(), f.y(), f.z()});
  }
  if (lastRow_ && lastRow_->step == s.step) {
    const bool changed = row.time != lastRow_->time || row.loadFactor != lastRow_->loadFactor ||
                         row.u != lastRow_->u || row.force != lastRow_->force;
    if (changed && writesProbes()) appendProbeRow(row, true);
    plotRows_.replaceLast(row);
  } else {
    if (writesProbes()) appendProbeRow(row, false);
    if (!lastRow_) plotRows_.capacity = PlotRows::capacityFor(3 + row.u.size() + row.force.size());
    plotRows_.add(row, lastRow_ ? &*lastRow_ : nullptr);
  }
  lastRow_ = std::move(row);
  lastPositions_ = x;
  if (s.velocity) lastVelocities_ = *s.velocity;
  const int stride = scene_.outputs.frameStride;
  if ((forceFrame || s.step % stride == 0) && s.step != lastFrameStep_) {
    writeFrame(s);
    lastFrameStep_ = s.step;
  }
}

void RunOutput::measureContactForces(std::vector<std::string> solids, ContactForceGauge gauge) {
  if (lastRow_)
    throw std::logic_error("RunOutput::measureContactForces: called after the first record()");
  contactSolids_ = std::move(solids);
  contactForces_ = contactSolids_.empty() ? ContactForceGauge() : std::move(gauge);
}

bool RunOutput::writesProbes() const {
  return scene_.outputs.probesCsv && (!model_.probes.empty() || !contactSolids_.empty());
}

int RunOutput::filesPerFrame() const {
  const std::size_t numActors = model_.actors.size();
  return numActors > 1 && numActors <= kMaxFramePartActors ? static_cast<int>(numActors) : 1;
}

void RunOutput::writeFrame(const StepState& s) {
  namespace fs = std::filesystem;
  const Eigen::VectorXd& x = *s.x;
  const Positions X = unflatten(x);
  const VtuFrame moving = movingVolumes_.empty() ? VtuFrame() : volumesFrame(movingVolumes_, s.time);
  if (scene_.outputs.vtu) {
    // One file for a single actor; with several, one per actor (a block each in ParaView), up to
    // kMaxFramePartActors; beyond, one file a frame again, its `actor` cell array telling the actors apart, so
    // that the files do not grow with actors x frames (100,000 actors wrote 300,000 files for 3 frames).
    const std::size_t numActors = model_.actors.size();
    const bool perActor = filesPerFrame() > 1;
    const std::string base = frameName(frames_, "vtu");
    std::string entries;
    lastFrame_.clear();
    for (std::size_t a = 0; a < (perActor ? numActors : 1); ++a) {
      const int v0 = perActor ? model_.actors[a].firstVertex : 0;
      const int nv = perActor ? model_.actors[a].numVertices : static_cast<int>(X.rows());
      const int f0 = perActor ? model_.actors[a].firstFace : 0;
      const int nf = perActor ? model_.actors[a].numFaces : static_cast<int>(model_.world.F.rows());
      VtuFrame frame;
      frame.points = X.middleRows(v0, nv);
      frame.triangles = model_.world.F.middleRows(f0, nf).array() - v0;
      VtuFrame::Array& u = frame.pointData["displacement"];
      u.components = 3;
      u.values.resize(3 * static_cast<std::size_t>(nv));
      for (int k = 0; k < 3 * nv; ++k)
        u.values[static_cast<std::size_t>(k)] = x[3 * v0 + k] - model_.world.V(v0 + k / 3, k % 3);
      if (s.velocity) {
        VtuFrame::Array& v = frame.pointData["velocity"];
        v.components = 3;
        v.values.assign(s.velocity->data() + 3 * v0, s.velocity->data() + 3 * (v0 + nv));
      }
      VtuFrame::Array& actor = frame.cellData["actor"];
      if (perActor) {
        actor.values.assign(static_cast<std::size_t>(nf), static_cast<double>(a));
      } else {
        for (std::size_t b = 0; b < numActors; ++b)
          actor.values.insert(actor.values.end(), static_cast<std::size_t>(model_.actors[b].numFaces), static_cast<double>(b));
      }
      const std::string name = perActor ? base.substr(0, base.size() - 4) + "_a" + std::to_string(a) + ".vtu" : base;
      lastFrame_.push_back((fs::path(directory_) / "frames" / name).string());
      writeFileAtomically(lastFrame_.back(), [&](std::ostream& out) { writeVtu(out, frame); });
      entries += PvdSeries::entry(s.time, "frames/" + name, static_cast<int>(a), perActor ? scene_.shells[a].name : "");
    }
    int part = perActor ? static_cast<int>(numActors) : 1;
    if (!staticVolumesFile_.empty())
      entries += PvdSeries::entry(s.time, "volumes.vtu", part++, perActor ? "volumes" : "");
    if (!movingVolumes_.empty())
      entries += PvdSeries::entry(s.time, writeMovingVolumes(moving), part, perActor ? "moving volumes" : "");
    if (!pvd_.isOpen()) pvd_.create((fs::path(directory_) / "frames.pvd").string(), PvdSeries::head(), PvdSeries::tail());
    pvd_.append(entries);
  }
  if (scene_.outputs.obj) {
    const std::string path = (fs::path(directory_) / "obj" / frameName(frames_, "obj")).string();
    writeFileAtomically(path, [&](std::ostream& out) { writeObj(out, X, model_.world.F); });
    if (!movingVolumes_.empty())
      writeFileAtomically((fs::path(directory_) / "obj" / movingVolumesName(frames_, "obj")).string(),
                          [&](std::ostream& out) { writeObj(out, moving.points, moving.triangles); });
  }
  ++frames_;
}

std::string RunOutput::writeMovingVolumes(const VtuFrame& placed) {
  const std::string name = "frames/" + movingVolumesName(frames_, "vtu");
  movingVolumesFile_ = (std::filesystem::path(directory_) / name).string();
  writeFileAtomically(movingVolumesFile_, [&](std::ostream& out) { writeVtu(out, placed); });
  return name;
}

std::vector<std::string> RunOutput::volumeFiles() const {
  std::vector<std::string> files;
  for (const std::string* f : {&staticVolumesFile_, &movingVolumesFile_})
    if (!f->empty()) files.push_back(*f);
  return files;
}

void RunOutput::appendProbeRow(const ProbeRow& r, bool overLastRow) {
  const std::string path = (std::filesystem::path(directory_) / "probes.csv").string();
  if (!probesCsv_.isOpen()) {
    std::ostringstream header;
    header << "step,time,load_factor";
    for (const ResolvedProbe& p : model_.probes)
      for (const char* axis : {"_ux", "_uy", "_uz"}) header << ',' << csvField(p.name + axis);
    for (const std::string& solid : contactSolids_)
      for (const char* axis : {"_Fx", "_Fy", "_Fz"}) header << ',' << csvField(solid + axis);
    header << '\n';
    probesCsv_.create(path, header.str(), "");
  } else if (overLastRow) {
    probesCsv_.reopen(path, lastRowOffset_, "");
  }
  lastRowOffset_ = probesCsv_.size();
  probesCsv_.append(csvRow(r));
}

PlotRows RunOutput::plotRows() const { return plotRows_.closedWith(lastRow_ ? &*lastRow_ : nullptr); }

std::map<std::string, Eigen::Vector3d> RunOutput::probeDisplacements() const {
  std::map<std::string, Eigen::Vector3d> out;
  if (!lastRow_) return out;
  const std::vector<double>& u = lastRow_->u;
  for (std::size_t k = 0; k < model_.probes.size(); ++k)
    out[model_.probes[k].name] = Eigen::Vector3d(u[3 * k], u[3 * k + 1], u[3 * k + 2]);
  return out;
}

OutputCheckpoint RunOutput::state() const {
  OutputCheckpoint o;
  o.frames = frames_;
  o.lastFrameStep = lastFrameStep_;
  for (const std::string& f : lastFrame_)
    o.lastFrame.push_back(std::filesystem::relative(f, directory_).generic_string());
  o.lastRow = lastRow_;
  o.plotRows = plotRows_;
  if (pvd_.isOpen()) o.pvdBytes = pvd_.size();
  if (probesCsv_.isOpen()) {
    o.probesBytes = probesCsv_.size();
    o.lastRowOffset = lastRowOffset_;
  }
  return o;
}

void RunOutput::restore(const OutputCheckpoint& o) {
  namespace fs = std::filesystem;
  frames_ = o.frames;
  lastFrameStep_ = o.lastFrameStep;
  lastFrame_.clear();
  for (const std::string& f : o.lastFrame) lastFrame_.push_back((fs::path(directory_) / f).string());
  lastRow_ = o.lastRow;
  plotRows_ = o.plotRows;
  lastRowOffset_ = o.lastRowOffset;
  movingVolumesFile_.clear();
  if (scene_.outputs.vtu && !movingVolumes_.empty() && frames_ > 0)
    movingVolumesFile_ = (fs::path(directory_) / "frames" / movingVolumesName(frames_ - 1, "vtu")).string();
  // probes.csv must end with the checkpoint's last row, where the checkpoint says it starts: a file replaced or
  // edited since would have been cut and continued as this run's. Checked first, before any file is cut.
  if (o.probesBytes) {
    const std::string path = (fs::path(directory_) / "probes.csv").string();
    const std::string last = lastRow_ ? csvRow(*lastRow_) : std::string();
    if (lastRow_ && *o.probesBytes - o.lastRowOffset != last.size())
      throw InputError(path + ": the checkpoint's last row is not where the checkpoint says (a damaged checkpoint)");
    probesCsv_.reopen(path, *o.probesBytes, "", last);
  }
  if (o.pvdBytes) pvd_.reopen((fs::path(directory_) / "frames.pvd").string(), *o.pvdBytes, PvdSeries::tail());
}

nlohmann::json RunOutput::actorSummaries() const {
  nlohmann::json actors = nlohmann::json::array();
  for (std::size_t a = 0; a < model_.actors.size(); ++a) {
    const ActorBlock& block = model_.actors[a];
    nlohmann::json entry = {{"name", scene_.shells[a].name}, {"layer", scene_.shells[a].layer},
                            {"vertices", block.numVertices}, {"faces", block.numFaces}};
    if (lastPositions_.size() == 3 * model_.world.numVertices() && block.numVertices > 0) {
      double maxDisplacement = 0.0, maxSpeed = 0.0;
      Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
      for (int v = block.firstVertex; v < block.firstVertex + block.numVertices; ++v) {
        const Eigen::Vector3d xv = lastPositions_.segment<3>(3 * v);
        maxDisplacement = std::max(maxDisplacement, (xv - model_.world.V.row(v).transpose()).norm());
        if (lastVelocities_.size() == lastPositions_.size()) maxSpeed = std::max(maxSpeed, lastVelocities_.segment<3>(3 * v).norm());
        lo = lo.cwiseMin(xv);
        hi = hi.cwiseMax(xv);
      }
      entry["max_displacement"] = maxDisplacement;
      if (lastVelocities_.size() == lastPositions_.size()) entry["max_speed"] = maxSpeed;
      entry["bounding_box"] = {{"min", {lo.x(), lo.y(), lo.z()}}, {"max", {hi.x(), hi.y(), hi.z()}}};
    }
    actors.push_back(std::move(entry));
  }
  return actors;
}

void RunOutput::finish(const RunSummary& summary) {
  namespace fs = std::filesystem;
  nlohmann::json j;
  j["scene"] = scenePath_;
  j["description"] = scene_.description;
  j["analysis"] = toString(scene_.analysis.type);
  j["converged"] = summary.converged;
  j["termination"] = summary.termination;
  j["steps"] = summary.steps;
  j["newton_iterations"] = summary.newtonIterations;
  j["wall_seconds"] = summary.wallSeconds;
  j["active_terms"] = summary.activeTerms;
  j["vertices"] = model_.numVertices();
  j["faces"] = model_.world.numFaces();
  nlohmann::json probes = nlohmann::json::object();
  for (const auto& [name, u] : probeDisplacements()) probes[name] = {u.x(), u.y(), u.z()};
  j["probes"] = probes;
  nlohmann::json picked = nlohmann::json::object();  // which vertex each probe reads, and where it sits at rest
  for (const ResolvedProbe& p : model_.probes)
    picked[p.name] = {{"vertex", p.vertex},
                      {"actor", scene_.shells[static_cast<std::size_t>(p.actor)].name},
                      {"reference_position", {p.reference.x(), p.reference.y(), p.reference.z()}}};
  j["probe_vertices"] = picked;
  j["actors"] = actorSummaries();
  if (lastRow_) {
    j["final_time"] = lastRow_->time;
    j["final_load_factor"] = lastRow_->loadFactor;
  }
  j["frames"] = frames_;
  if (!contactSolids_.empty() && lastRow_) {  // the force on each volume actor in the last state
    nlohmann::json forces = nlohmann::json::object();
    const std::vector<double>& f = lastRow_->force;
    for (std::size_t k = 0; k < contactSolids_.size(); ++k)
      forces[contactSolids_[k]] = {f[3 * k], f[3 * k + 1], f[3 * k + 2]};
    j["contact_forces"] = forces;
  }
  j["unsupported"] = unsupportedFeatures(scene_);
  for (const auto& item : summary.extra.items()) j[item.key()] = item.value();
  writeFileAtomically((fs::path(directory_) / "summary.json").string(), j.dump(2) + "\n");
}

}  // namespace jetshell
