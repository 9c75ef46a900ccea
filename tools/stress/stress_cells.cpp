#include "tools/stress/stress_cells.h"

#include "core/format.h"
#include "core/mesh.h"
#include "tools/scene/run_scene.h"
#include "tools/scene/scene_json.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace jetshell {
namespace {

using Json = nlohmann::json;

std::string sci(double v) { return formatNumber("%g", v); }

Json rectangle(double w, double h, int nx, int ny) {
  return {{"generator", "rectangle"}, {"width", w}, {"height", h}, {"nx", nx}, {"ny", ny}};
}

Json plate(double E, double nu, double h, double rho = 1000.0) {
  return {{"youngsModulus", E}, {"poissonRatio", nu}, {"thickness", h}, {"volumeDensity", rho}};
}

Json shell(const Json& shape, const Json& material, const Json& fixed, const Json& loads) {
  return {{"type", "shell"},         {"name", "sheet"},  {"shape", shape},  {"material", material},
          {"colliderType", "None"}, {"fixed", fixed},   {"loads", loads}, {"probes", {{{"name", "P"}, {"select", {{"nearest", {1.0, 1.0, 0.0}}}}}}}};
}

Json scene(const Json& actor, const Json& analysis, const Json& gravity = {0.0, 0.0, -9.81}, Json solver = Json::object()) {
  solver["threads"] = 1;
  return {{"description", "stress cell"}, {"gravity", gravity}, {"actors", {actor}},
          {"analysis", analysis},         {"solver", solver},   {"outputs", {{"png", false}, {"plots", false}}}};
}

const Json kClampLeft = {{{"select", {{"group", "left"}}}, {"clampRotation", true}}};
/// The same for inline meshes (no groups): the vertices at x = 0.
const Json kClampLeftArrays = {{{"select", {{"box", {{"min", {-1e-9, -10.0, -10.0}}, {"max", {1e-9, 10.0, 10.0}}}}}}, {"clampRotation", true}}};
Json staticSteps(int n) { return {{"type", "static"}, {"loadSteps", n}}; }
Json dynamic(double dt, int steps, const char* integrator = "backwardEuler") {
  return {{"type", "dynamic"}, {"timeStep", dt}, {"duration", dt * steps}, {"integrator", integrator}};
}
Json tipLoad(double fz) { return {{{"select", {{"group", "right"}}}, {"force", {0.0, 0.0, fz}}, {"distribution", "edgeLength"}}}; }

/// A cantilever: 1 m × 1 m, 6 × 6 quads, clamped on the left, under its weight and a tip load.
Json cantilever(const Json& material, double tip, const Json& analysis, const Json& gravity = {0.0, 0.0, -9.81}) {
  return scene(shell(rectangle(1.0, 1.0, 6, 6), material, kClampLeft, tip != 0.0 ? tipLoad(tip) : Json::array()), analysis,
               gravity);
}

/// A cloth 0.1 m above a floor plane (z = 0), falling under `g` (m/s²) into it, with point-cloud self-contact.
Json clothOnFloor(double g, double radius, int n, const Json& analysis) {
  Json cloth = shell(rectangle(1.0, 1.0, n, n), plate(1e5, 0.25, 0.002), Json::array(), Json::array());
  cloth["colliderType"] = "PointCloud";
  cloth["pointCloudCollider"] = {{"radius", radius}, {"selfContact", true}};
  cloth["worldFromLocalTransform"] = {{"translation", {0.0, 0.0, 0.1}}};
  const Json floor = {{"type", "plane"}, {"name", "floor"}, {"point", {0.0, 0.0, 0.0}}, {"normal", {0.0, 0.0, 1.0}},
                      {"contact", {{"penaltyStiffness", 1e6}}}};
  Json s = scene(cloth, analysis, {0.0, 0.0, -g});
  s["actors"].push_back(floor);
  return s;
}

/// A cloth (n × n quads, 1 m, 0.1 m above z = 0) falling under `g` onto `volume` with the volume's contact
/// parameters; with `radius` > 0 it is a point cloud with self-contact, else it has no collider of its own.
Json clothOver(const Json& volume, double g, int n, double radius, const Json& analysis) {
  Json cloth = shell(rectangle(1.0, 1.0, n, n), plate(1e5, 0.25, 0.002), Json::array(), Json::array());
  if (radius > 0.0) {
    cloth["colliderType"] = "PointCloud";
    cloth["pointCloudCollider"] = {{"radius", radius}, {"selfContact", true}};
  }
  cloth["worldFromLocalTransform"] = {{"translation", {-0.5, -0.5, 0.1}}};
  cloth["probes"] = {{{"name", "P"}, {"select", {{"nearest", {0.5, 0.5, 0.1}}}}}};
  Json s = scene(cloth, analysis, {0.0, 0.0, -g});
  s["actors"].push_back(volume);
  return s;
}

/// A cloth pinned at its two top corners.
Json hangingCloth(const Json& shape, const Json& analysis, Json solver = Json::object()) {
  const Json pins = {{{"select", {{"nearest", {0.0, 1.0, 0.0}}}}}, {{"select", {{"nearest", {1.0, 1.0, 0.0}}}}}};
  return scene(shell(shape, plate(1e6, 0.3, 1e-3, 200.0), pins, Json::array()), analysis, {0.0, -9.81, 0.0}, std::move(solver));
}

/// Two 1 m squares (nx × n quads each) joined along x = 1, the right one folded back by `degrees` about that
/// line (180° would lay it onto the left one).
Json foldedSheet(double degrees, int n) {
  const double phi = degrees * M_PI / 180.0;
  Json V = Json::array(), F = Json::array();
  const int columns = 2 * n + 1;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i < columns; ++i) {
      const double y = static_cast<double>(j) / n;
      if (i <= n) {
        V.push_back({static_cast<double>(i) / n, y, 0.0});
      } else {
        const double s = static_cast<double>(i - n) / n;
        V.push_back({1.0 + s * std::cos(phi), y, s * std::sin(phi)});
      }
    }
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < columns - 1; ++i) {
      const int a = j * columns + i, b = a + 1, c = a + columns, d = c + 1;
      F.push_back({a, b, d});
      F.push_back({a, d, c});
    }
  return {{"vertices", V}, {"faces", F}};
}

/// A 6 × 6 sheet crumpled at rest: a deterministic out-of-plane pattern of about half the edge length.
Json crumpledSheet() {
  const int n = 6;
  Json V = Json::array(), F = Json::array();
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const double x = static_cast<double>(i) / n, y = static_cast<double>(j) / n;
      V.push_back({x, y, 0.09 * std::sin(17.3 * x + 5.1 * y) * std::cos(11.7 * y - 3.0 * x)});
    }
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
      F.push_back({a, b, d});
      F.push_back({a, d, c});
    }
  return {{"vertices", V}, {"faces", F}};
}

void add(std::vector<StressCell>& cells, bool quickOnly, bool quick, std::string name, std::string what, Json s,
         int stepLimit = 0) {
  if (quickOnly && !quick) return;
  cells.push_back({std::move(name), std::move(what), std::move(s), stepLimit, quick});
}

bool hasNonFiniteToken(const std::string& text) {
  // Numbers are written by formatDouble/printf: a non-finite one reads "nan", "-nan", "inf" or "-inf".
  std::string lower(text.size(), ' ');
  std::transform(text.begin(), text.end(), lower.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  for (const char* token : {"nan", "inf"}) {
    for (std::size_t at = lower.find(token); at != std::string::npos; at = lower.find(token, at + 1)) {
      const bool startOk = at == 0 || !std::isalpha(static_cast<unsigned char>(lower[at - 1]));
      const std::size_t end = at + 3;
      const bool endOk = end >= lower.size() || !std::isalpha(static_cast<unsigned char>(lower[end])) ||
                         lower.compare(at, 8, "infinity") == 0;
      if (startOk && endOk) return true;
    }
  }
  return false;
}

std::string firstNull(const Json& j, const std::string& pointer) {
  if (j.is_null()) return pointer.empty() ? "/" : pointer;
  if (j.is_object() || j.is_array()) {
    for (auto it = j.begin(); it != j.end(); ++it) {
      const std::string key = j.is_object() ? it.key() : std::to_string(std::distance(j.begin(), it));
      const std::string found = firstNull(*it, pointer + "/" + key);
      if (!found.empty()) return found;
    }
  }
  return "";
}

}  // namespace

std::vector<StressCell> stressCells(bool q) {
  std::vector<StressCell> c;
  for (double h : {1e-5, 1e-4, 1e-3, 1e-2, 1e-1})
    add(c, q, h == 1e-5 || h == 1e-1, "thickness/h_L=" + sci(h), "cantilever under its weight, E 1e9 Pa, nu 0.3",
        cantilever(plate(1e9, 0.3, h), 0.0, staticSteps(4)));
  for (double E : {1e2, 1e4, 1e6, 1e8, 1e10, 1e12})
    add(c, q, E == 1e2 || E == 1e12, "young/E=" + sci(E), "cantilever under its weight and a tip load, h 0.01 m",
        cantilever(plate(E, 0.3, 0.01), -1.0, staticSteps(4)));
  for (double nu : {-0.9, -0.5, 0.0, 0.3, 0.49})
    add(c, q, nu == -0.9 || nu == 0.49, "poisson/nu=" + sci(nu), "cantilever under a tip load, E 1e6 Pa, h 0.01 m",
        cantilever(plate(1e6, nu, 0.01), -0.1, staticSteps(4)));
  for (double dt : {1e-5, 1e-4, 1e-3, 1e-2, 1e-1})
    add(c, q, dt == 1e-5 || dt == 1e-1, "time_step/dt=" + sci(dt), "hanging cloth, 5 backward Euler steps",
        hangingCloth(rectangle(1.0, 1.0, 6, 6), dynamic(dt, 5)));
  add(c, q, false, "time_step/bdf2_dt=0.1", "hanging cloth, 5 BDF2 steps of 0.1 s",
      hangingCloth(rectangle(1.0, 1.0, 6, 6), dynamic(0.1, 5, "bdf2")));
  add(c, q, true, "iteration_cap/move_on", "hanging cloth, 0.1 s steps, 2 Newton iterations then move on",
      hangingCloth(rectangle(1.0, 1.0, 6, 6), dynamic(0.1, 5), {{"maxIterations", 2}, {"acceptIterationCap", true}}));
  add(c, q, false, "iteration_cap/stop", "hanging cloth, 0.1 s steps, 1 Newton iteration, cut on the cap",
      hangingCloth(rectangle(1.0, 1.0, 6, 6), dynamic(0.1, 5), {{"maxIterations", 1}}));
  for (int steps : {1, 50})
    add(c, q, steps == 1, "load_steps/n=" + std::to_string(steps), "cantilever, tip load bending it far past its length",
        cantilever(plate(1e6, 0.0, 0.01, 0.0), -1.0, staticSteps(steps)));
  add(c, q, true, "sliver/static", "cantilever of 0.5 m x 5 mm triangles (angles 0.57 deg) under a tip load",
      scene(shell(rectangle(1.0, 0.02, 2, 4), plate(1e6, 0.3, 0.001), kClampLeft, tipLoad(-1e-3)), staticSteps(4)));
  add(c, q, false, "sliver/dynamic", "hanging strip of sliver triangles, 5 steps of 0.01 s",
      hangingCloth(rectangle(1.0, 0.02, 2, 4), dynamic(0.01, 5)));
  for (double fold : {170.0, 179.0, 179.9})
    add(c, q, fold == 179.9, "fold/rest_" + sci(fold) + "deg", "rest mesh folded back by this angle, clamped, weight",
        scene(shell(foldedSheet(fold, 3), plate(1e6, 0.3, 0.01), kClampLeftArrays, Json::array()), staticSteps(2)));
  add(c, q, false, "fold/dynamic_179deg", "rest mesh folded back by 179 deg, falling, 5 steps of 0.01 s",
      hangingCloth(foldedSheet(179.0, 3), dynamic(0.01, 5)));
  add(c, q, true, "crumpled/rest_dynamic", "crumpled rest mesh, pinned, 5 steps of 0.01 s",
      hangingCloth(crumpledSheet(), dynamic(0.01, 5)));
  add(c, q, false, "crumpled/rest_static", "crumpled rest mesh, clamped, weight and tip load",
      scene(shell(crumpledSheet(), plate(1e6, 0.3, 0.01), kClampLeftArrays,
                  {{{"select", {{"nearest", {1.0, 1.0, 0.0}}}}, {"force", {0.0, 0.0, -0.1}}}}), staticSteps(4)));
  add(c, q, false, "crumpled/compressed", "flat sheet pushed to 20% of its length between clamped edges",
      scene(shell(rectangle(1.0, 1.0, 6, 6), plate(1e6, 0.3, 0.01),
                  {{{"select", {{"group", "left"}}}, {"clampRotation", true}},
                   {{"select", {{"group", "right"}}}, {"displacement", {-0.8, 0.0, 0.0}}, {"clampRotation", true}}},
                  Json::array()),
            staticSteps(8)));
  add(c, q, true, "singular/no_supports", "static, no fixed vertex, under its weight: a rigid-body mode",
      scene(shell(rectangle(1.0, 1.0, 6, 6), plate(1e6, 0.3, 0.01), Json::array(), Json::array()), staticSteps(4)));
  add(c, q, false, "singular/no_supports_pcg_jacobi", "the same with PCG + Jacobi",
      scene(shell(rectangle(1.0, 1.0, 6, 6), plate(1e6, 0.3, 0.01), Json::array(), Json::array()), staticSteps(4),
            {0.0, 0.0, -9.81}, {{"linearSolver", "pcg"}, {"preconditioner", "jacobi"}}));
  add(c, q, false, "singular/x_free", "static, fixed in z only, pushed along x",
      scene(shell(rectangle(1.0, 1.0, 6, 6), plate(1e6, 0.3, 0.01), {{{"select", {{"group", "left"}}}, {"components", "z"}}},
                  {{{"select", {{"group", "right"}}}, {"force", {1.0, 0.0, 0.0}}}}),
            staticSteps(4)));
  add(c, q, true, "invert/pushed_vertex", "membrane with a fixed rim, one inner vertex dragged past its neighbours",
      scene(shell(rectangle(1.0, 1.0, 4, 4), {{"membraneLambda", 100.0}, {"membraneMu", 100.0}, {"bendingAlpha", 0.0}, {"bendingBeta", 1e-6}},
                  {{{"select", {{"boundary", true}}}}, {{"select", {{"indices", {6}}}}, {"displacement", {0.6, 0.6, 0.0}}}},
                  Json::array()),
            staticSteps(4), {0.0, 0.0, 0.0}));
  add(c, q, false, "invert/crushing_load", "a 1e4 N in-plane load on one corner of a soft clamped sheet",
      scene(shell(rectangle(1.0, 1.0, 4, 4), plate(1e4, 0.3, 0.001), kClampLeft,
                  {{{"select", {{"nearest", {1.0, 1.0, 0.0}}}}, {"force", {-1e4, -1e4, 0.0}}}}),
            staticSteps(4), {0.0, 0.0, 0.0}));
  add(c, q, false, "extreme/twist_720deg", "a strip's end twisted by 720 deg in 4 load steps",
      scene(shell(rectangle(1.0, 0.2, 10, 2), plate(1e6, 0.3, 0.01), {{{"select", {{"group", "left"}}}, {"clampRotation", true}},
                  {{"select", {{"group", "right"}}}, {"rotation", {{"axis", {1.0, 0.0, 0.0}}, {"center", {1.0, 0.1, 0.0}}, {"degrees", 720.0}}}}},
                  Json::array()),
            staticSteps(4), {0.0, 0.0, 0.0}));
  add(c, q, true, "contact/fast_impact_plane", "cloth hitting a floor plane at about 6 m/s (200 m/s^2 gravity), 60 Hz",
      clothOnFloor(200.0, 0.02, 8, dynamic(1.0 / 60.0, 8)));
  add(c, q, false, "contact/thin_layer_self_contact", "cloth with 5 mm point radius falling flat onto the floor, 60 Hz",
      clothOnFloor(9.81, 0.005, 10, dynamic(1.0 / 60.0, 12)));
  add(c, q, false, "extreme/gravity_1e6", "cantilever under 1e6 m/s^2 gravity",
      cantilever(plate(1e6, 0.3, 0.01), 0.0, staticSteps(4), {0.0, 0.0, -1e6}));
  add(c, q, false, "extreme/displacement_1e3", "clamped sheet with its far edge moved by 1 km",
      scene(shell(rectangle(1.0, 1.0, 6, 6), plate(1e6, 0.3, 0.01),
                  {{{"select", {{"group", "left"}}}, {"clampRotation", true}},
                   {{"select", {{"group", "right"}}}, {"displacement", {0.0, 0.0, 1e3}}}},
                  Json::array()),
            staticSteps(4)));
  // Contact at the edges of its parameters and colliders.
  const Json sphere = {{"type", "sphere"}, {"name", "ball"}, {"center", {0.0, 0.0, -0.3}}, {"radius", 0.35}};
  Json stiffBall = sphere;
  stiffBall["contact"] = {{"penaltyStiffness", 1e13}};
  add(c, q, false, "contact/penalty_1e13_sphere", "cloth falling onto a ball with a 1e13 Pa/m penalty, 60 Hz",
      clothOver(stiffBall, 9.81, 8, 0.0, dynamic(1.0 / 60.0, 12)));
  Json softBall = sphere;
  softBall["contact"] = {{"penaltyStiffness", 1.0}};
  add(c, q, false, "contact/penalty_1_sphere", "cloth falling onto a ball with a 1 Pa/m penalty (sinks in), 60 Hz",
      clothOver(softBall, 9.81, 8, 0.0, dynamic(1.0 / 60.0, 12)));
  const Json spinning = {{"type", "box"}, {"name", "spinner"}, {"center", {0.0, 0.0, -0.1}},
                         {"halfExtents", {0.3, 0.3, 0.1}}, {"angularVelocity", {0.0, 0.0, 60.0}}};
  add(c, q, false, "contact/spinning_box", "cloth falling onto a box spinning at 60 rad/s, friction 0.5, 60 Hz",
      clothOver(spinning, 9.81, 8, 0.0, dynamic(1.0 / 60.0, 12)));
  const Json bullet = {{"type", "capsule"},          {"name", "bullet"},
                       {"center", {0.0, 0.0, -0.2}}, {"radius", 0.05},
                       {"halfLength", 0.1},          {"velocity", {0.0, 0.0, 30.0}}};
  add(c, q, true, "contact/capsule_at_30m_s", "capsule rising at 30 m/s through a falling cloth, 60 Hz",
      clothOver(bullet, 9.81, 8, 0.0, dynamic(1.0 / 60.0, 6)));
  Json faster = bullet;
  faster["velocity"] = {0.0, 0.0, 300.0};
  add(c, q, false, "contact/capsule_at_300m_s", "capsule rising at 300 m/s (5 m a step) through a cloth, 60 Hz",
      clothOver(faster, 9.81, 8, 0.0, dynamic(1.0 / 60.0, 6)));
  const Json jerk = {{"type", "box"},
                     {"name", "jerk"},
                     {"center", {0.0, 0.0, -0.02}},
                     {"halfExtents", {0.3, 0.3, 0.02}},
                     {"keyframes", {{{"time", 0.1}, {"translation", {0.0, 0.0, 0.5}}},
                                    {{"time", 0.15}, {"translation", {0.3, 0.0, 0.2}},
                                     {"rotation", {{"axis", {0.0, 0.0, 1.0}}, {"degrees", 170.0}}}}}}};
  add(c, q, false, "contact/keyframed_jerk", "thin tray jerked up 0.5 m in 0.1 s, then aside and turned, under a cloth",
      clothOver(jerk, 9.81, 8, 0.0, dynamic(1.0 / 60.0, 30)));
  // A solid pressed into a sheet along a static path (its keyframes read with the load factor as time): a thin
  // ball driven 10 cm through the sheet's plane in one load step, which must be divided so that it cannot pass
  // through unseen; and one too thin for the bound to follow, refused by name.
  for (const double radius : {0.01, 1e-5}) {
    Json s = scene(shell(rectangle(0.4, 0.4, 32, 32), plate(1e7, 0.3, 0.001), {{{"select", {{"boundary", true}}}}},
                         Json::array()),
                   staticSteps(1), {0.0, 0.0, 0.0});
    s["actors"][0]["probes"][0]["select"] = {{"nearest", {0.2, 0.2, 0.0}}};
    s["actors"].push_back({{"type", "sphere"}, {"name", "punch"}, {"center", {0.2, 0.2, 0.01 + radius}},
                           {"radius", radius}, {"keyframes", {{{"time", 1.0}, {"translation", {0.0, 0.0, -0.1}}}}}});
    add(c, q, false, radius > 1e-3 ? "contact/static_press_thin_ball" : "contact/static_press_needle",
        radius > 1e-3 ? "ball of radius 1 cm pressed 9 cm into a fixed sheet in one static load step"
                      : "ball of radius 10 um pressed 9 cm into a fixed sheet in one static load step",
        s);
  }
  // A bar pressed 8 cm into a sheet held at two edges and turned 90° in it along a static path: with sharp edges
  // (the distance has no curvature across them to settle the sheet on) and rounded by 1 cm.
  for (const double edgeRadius : {0.0, 0.01}) {
    const Json edges = Json::array({Json{{"group", "left"}}, Json{{"group", "right"}}});
    Json s = scene(shell(rectangle(0.4, 0.4, 12, 12), plate(1e6, 0.3, 0.001), Json::array({Json{{"select", edges}}}),
                         Json::array()),
                   staticSteps(10));
    s["actors"][0]["probes"][0]["select"] = {{"nearest", {0.2, 0.2, 0.0}}};
    s["actors"].push_back(
        {{"type", "box"}, {"name", "bar"}, {"center", {0.2, 0.2, 0.03}}, {"halfExtents", {0.15, 0.02, 0.02}},
         {"edgeRadius", edgeRadius},
         {"keyframes", {{{"time", 0.5}, {"translation", {0.0, 0.0, -0.08}}},
                        {{"time", 1.0}, {"translation", {0.0, 0.0, -0.08}},
                         {"rotation", {{"axis", {0.0, 0.0, 1.0}}, {"degrees", 90.0}}}}}}});
    add(c, q, false, edgeRadius > 0.0 ? "contact/static_turned_bar_rounded" : "contact/static_turned_bar_sharp",
        edgeRadius > 0.0 ? "bar with 1 cm rounded edges pressed 8 cm into a sheet and turned 90 deg, static path"
                         : "bar with sharp edges pressed 8 cm into a sheet and turned 90 deg, static path",
        s);
  }
  Json incline = {{"type", "plane"}, {"name", "incline"}, {"point", {0.0, 0.0, 0.0}}, {"normal", {0.0, 0.5, 0.866}}};
  for (double mu : {0.0, 100.0}) {
    incline["contact"] = {{"frictionCoefficient", mu}};
    Json s = clothOver(incline, 9.81, 6, 0.0, dynamic(1.0 / 60.0, 12));
    s["actors"][0]["contact"] = {{"frictionCoefficient", mu}};
    add(c, q, false, "contact/incline_friction_" + sci(mu), "cloth landing on a 30 deg incline, this friction, 60 Hz",
        s);
  }
  {
    Json s = clothOver({{"type", "plane"}, {"name", "floor"}}, 9.81, 8, 0.02, dynamic(1.0 / 60.0, 12, "bdf2"));
    Json top = s["actors"][0];
    top["name"] = "top";
    top["worldFromLocalTransform"] = {{"translation", {-0.45, -0.5, 0.13}}};
    top["probes"][0]["name"] = "Q";
    s["actors"].push_back(top);
    add(c, q, false, "contact/two_cloths_bdf2", "two point-cloud cloths 3 cm apart falling on a floor, BDF2, 60 Hz",
        s);
  }
  // The other static solvers: relaxation and path following.
  add(c, q, false, "relaxation/thin_h_L=1e-05", "cantilever of h/L 1e-5 under its weight by dynamic relaxation",
      cantilever(plate(1e9, 0.3, 1e-5), 0.0,
                 {{"type", "dynamicRelaxation"}, {"timeStep", 0.01}, {"massDamping", 5.0}, {"maxSteps", 2000}}));
  add(c, q, false, "relaxation/no_supports", "dynamic relaxation of an unsupported sheet under its weight",
      scene(shell(rectangle(1.0, 1.0, 6, 6), plate(1e6, 0.3, 0.01), Json::array(), Json::array()),
            {{"type", "dynamicRelaxation"}, {"timeStep", 0.01}, {"massDamping", 5.0}, {"maxSteps", 200}}));
  add(c, q, false, "path/arc_length_compressed", "sheet pushed to 20% of its length by arc length",
      scene(shell(rectangle(1.0, 1.0, 6, 6), plate(1e6, 0.3, 0.01),
                  {{{"select", {{"group", "left"}}}, {"clampRotation", true}},
                   {{"select", {{"group", "right"}}}, {"displacement", {-0.8, 0.0, 0.0}}, {"clampRotation", true}}},
                  Json::array()),
            {{"type", "static"}, {"loadSteps", 8}, {"pathControl", {{"type", "arcLength"}, {"maxSteps", 300}}}}));
  add(c, q, false, "path/displacement_past_length", "cantilever tip driven 3 m down (past its length) by its load",
      cantilever(plate(1e6, 0.3, 0.01), -1.0,
                 {{"type", "static"},
                  {"loadSteps", 4},
                  {"pathControl",
                   {{"type", "displacement"}, {"probe", "P"}, {"component", "z"}, {"displacement", -3.0}}}},
                 {0.0, 0.0, 0.0}));
  return c;
}

std::string findNonFinite(const std::string& directory) {
  namespace fs = std::filesystem;
  std::error_code ec;
  for (fs::recursive_directory_iterator it(directory, ec), end; !ec && it != end; it.increment(ec)) {
    if (!it->is_regular_file()) continue;
    const fs::path& p = it->path();
    std::ifstream in(p, std::ios::binary);
    std::stringstream text;
    text << in.rdbuf();
    const std::string ext = p.extension().string();
    if (p.filename() == "summary.json") {
      const Json j = Json::parse(text.str(), nullptr, false);
      if (j.is_discarded()) return p.string() + " (not valid JSON)";
      const std::string pointer = firstNull(j, "");
      if (!pointer.empty()) return p.string() + " (null at " + pointer + ")";
    } else if ((ext == ".vtu" || ext == ".pvd" || ext == ".csv" || ext == ".obj") && hasNonFiniteToken(text.str())) {
      return p.string();
    }
  }
  return "";
}

nlohmann::json runStressCell(const StressCell& cell, const std::string& outputDirectory) {
  Json r = {{"name", cell.name}, {"what", cell.what}};
  try {
    const Scene scene = sceneFromJson(cell.scene, ".");
    RunOptions o;
    o.outputDirectory = outputDirectory;
    o.stepLimit = cell.stepLimit;
    o.pictures = false;
    const RunResult run = runScene(scene, o);
    const RunSummary& s = run.summary;
    const bool ok = s.converged || run.stepLimitReached;
    r["outcome"] = ok ? "ok" : "failed_cleanly";
    std::string reason = s.termination;
    for (const std::string& w : run.warnings) reason += "; warning: " + w;
    r["reason"] = reason;
    r["termination"] = s.termination;
    r["steps"] = s.steps;
    r["newton_iterations"] = s.newtonIterations;
    r["warnings"] = run.warnings;
    for (const char* key : {"inverted_faces", "load_step_cuts", "step_cuts", "safeguards"})
      if (s.extra.contains(key)) r[key] = s.extra[key];
  } catch (const InputError& e) {
    r["outcome"] = "failed_cleanly";
    r["reason"] = std::string("refused: ") + e.what();
  } catch (const std::exception& e) {
    r["outcome"] = "defect";
    r["reason"] = std::string("internal error: ") + e.what();
  }
  const std::string bad = findNonFinite(outputDirectory);
  if (!bad.empty()) {
    r["outcome"] = "defect";
    r["reason"] = "non-finite number in " + bad + " (" + r["reason"].get<std::string>() + ")";
  }
  return r;
}

}  // namespace jetshell
