// A static scene's path control (SCENES.md "Path following") as the statics path's options
// (solvers/path_control.h): arc length as it is; displacement control's probe resolved to the dof it drives.
//
// Inputs: the validated settings, the resolved scene model (its probes' vertices) and the shell system built
// from it. Output: PathFollowingOptions. Throws InputError naming /analysis/pathControl when the driven dof is
// fixed by a boundary condition.
#pragma once

#include "solvers/path_control.h"
#include "solvers/shell_system.h"
#include "tools/scene/scene.h"
#include "tools/scene/scene_model.h"

namespace jetshell {

void setPathControl(const PathControlSettings& settings, const SceneModel& model, ShellSystem& system,
                    PathFollowingOptions& out);

}  // namespace jetshell
