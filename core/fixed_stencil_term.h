// The state every term over a fixed stencil table shares: its name, the table (K vertex ids per element), the
// parallel schedule of its elements (core/assembly.h) and the conformance flags. ElementEnergyTerm
// (energies/element_energy_term.h) and StageGraphTerm (core/stage_graph_term.h) derive from it and add how an
// element is differentiated.
#pragma once

#include "core/assembly.h"
#include "core/term.h"

#include <string>
#include <utility>
#include <vector>

namespace jetshell {

class FixedStencilTerm : public EnergyTerm {
 public:
  FixedStencilTerm(std::string name, StencilTable stencils, int numVertices, bool zeroAtRest, bool rigidInvariant)
      : name_(std::move(name)),
        table_(std::move(stencils)),
        schedule_(scheduleElements(table_, numVertices)),
        zeroAtRest_(zeroAtRest),
        rigidInvariant_(rigidInvariant) {}

  std::string name() const override { return name_; }
  StencilTable stencils() const override { return table_; }
  bool zeroAtRest() const override { return zeroAtRest_; }
  bool rigidInvariant() const override { return rigidInvariant_; }

 protected:
  std::string name_;
  StencilTable table_;
  ElementSchedule schedule_;
  bool zeroAtRest_, rigidInvariant_;
  std::vector<double> elementEnergy_;  // per element, summed in a fixed order by the element loop
};

}  // namespace jetshell
