// The run's plots (SCENES.md, Outputs, `plots`): probes.png, each probe's displacement over the run, and
// contact_forces.png, the force each volume actor takes from the shells. Curves are coloured by component (x red,
// y green, z blue) and dashed by probe or solid; components that stay at zero are left out.
#pragma once

#include "tools/output/run_checkpoint.h"
#include "tools/render/plot.h"

#include <string>
#include <vector>

namespace jetshell {

/// One curve per component of each named vector series: `values[3 k + c]` is component c of `names[k]` at each
/// abscissa; `symbol` names the quantity in the legend ("u" gives "B ux"). Components whose largest magnitude
/// is at most 1e-3 of the largest of all are left out.
std::vector<PlotSeries> componentCurves(const std::vector<std::string>& names, const std::string& symbol,
                                        const std::vector<double>& abscissa,
                                        const std::vector<std::vector<double>>& values);

/// contact_forces.png's curves from probes.csv's rows: three values per solid in each row's `force`.
std::vector<PlotSeries> contactForceCurves(const std::vector<std::string>& solids, const std::vector<ProbeRow>& rows);

}  // namespace jetshell
