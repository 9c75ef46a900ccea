// From a resolved scene to the solver's problem: every shell actor with its own material, gravity flag, clamps,
// contact parameters, contact sampling and point-cloud collider over the stacked unknowns, the rigid volume
// actors as colliders, prescribed coordinates and applied forces. Input: a validated Scene and its SceneModel.
// Output: a ShellProblem (solvers/shell_system.h). Throws InputError for an unreadable SDF grid file.
#pragma once

#include "solvers/shell_system.h"
#include "tools/scene/scene.h"
#include "tools/scene/scene_model.h"

namespace jetshell {

ShellProblem shellProblemFromScene(const Scene& scene, const SceneModel& model);

}  // namespace jetshell
