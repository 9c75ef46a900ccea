// The contact terms as the registry (energies/registry.h) enrols them: each built on the small check meshes
// with a collider or pair set placed through the mesh, and coefficients scaled to the mesh's size, so that the
// check configurations land in every part of the ramp (no contact, the rounded corner, the linear part) and
// of the friction primitive (sticking and sliding).
#pragma once

#include "energies/registry.h"

#include <vector>

namespace jetshell {

std::vector<RegisteredTerm> contactRegistryEntries();

}  // namespace jetshell
