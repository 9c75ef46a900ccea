#include "tools/scene/scene_path_control.h"

#include "core/mesh.h"

namespace jetshell {

void setPathControl(const PathControlSettings& c, const SceneModel& model, ShellSystem& system,
                    PathFollowingOptions& out) {
  out = PathFollowingOptions{};
  if (c.type == "load") return;
  out.maxSteps = c.maxSteps;
  out.loadScaling = c.loadScaling;
  if (c.type == "arcLength") {
    out.control = PathControl::ArcLength;
    return;
  }
  out.control = PathControl::Displacement;
  const ResolvedProbe* probe = nullptr;
  for (const ResolvedProbe& p : model.probes)
    if (p.name == c.probe) probe = &p;
  if (probe == nullptr) throw InputError("/analysis/pathControl/probe = \"" + c.probe + "\": no probe has this name");
  out.controlledDof = 3 * probe->vertex + c.component;
  out.displacement = c.displacement;
  Objective& objective = system.objective();
  if (!objective.finalized()) objective.finalize();
  if (objective.fixedDof()[static_cast<std::size_t>(out.controlledDof)])
    throw InputError("/analysis/pathControl/probe = \"" + c.probe + "\": its vertex is fixed in " +
                     std::string(1, static_cast<char>('x' + c.component)) +
                     " by a boundary condition; displacement control drives a free component");
}

}  // namespace jetshell
