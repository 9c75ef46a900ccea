// The run's plots (SCENES.md, Outputs, `plots`): probes.png, each probe's displacement over the run, and
// contact_forces.png, the force each volume actor takes from the shells. Curves are coloured by component (x red,
// y green, z blue) and dashed by probe or solid; components that stay at zero are left out.
#pragma once

#include "tools/output/plot_rows.h"
#include "tools/render/plot.h"

#include <string>
#include <vector>

namespace jetshell {

/// The curves of one field of probes.csv's rows against their time: three values per name in each row's `field`
/// (ProbeRow::u, one name per probe; ProbeRow::force, one per solid). Rows of another length are skipped.
/// `symbol` names the quantity in the legend ("u" gives "B ux"). Components whose largest magnitude is at most
/// 1e-3 of the largest of all are left out.
std::vector<PlotSeries> rowCurves(const std::vector<std::string>& names, const std::string& symbol,
                                  const std::vector<ProbeRow>& rows, std::vector<double> ProbeRow::*field);

}  // namespace jetshell
