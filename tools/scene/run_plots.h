// The run's plots (SCENES.md, Outputs, `plots`): probes.png, each probe's displacement over the run, and
// contact_forces.png, the force each volume actor takes from the shells. Curves are coloured by component (x red,
// y green, z blue) and dashed by probe or solid; components that stay at zero are left out.
#pragma once

#include "tools/output/plot_rows.h"
#include "tools/render/plot.h"

#include <optional>
#include <string>
#include <vector>

namespace jetshell {

/// A field of probes.csv's rows: the probes' displacements (ProbeRow::u) or the solids' forces (ProbeRow::force).
enum class RowField { u, force };

/// The curves of one field of the kept rows against their time: three values per name (one name per probe for u,
/// one per solid for force). Each bucket of rows is drawn at its first row's time from its first row's value
/// through its least and greatest (so a peak shorter than the bucket is drawn, at most a bucket early), then the
/// last recorded row `last`. Rows of another length are skipped. `symbol` names the quantity in the legend ("u"
/// gives "B ux"). Components whose largest magnitude is at most 1e-3 of the largest of all are left out.
std::vector<PlotSeries> rowCurves(const std::vector<std::string>& names, const std::string& symbol,
                                  const PlotRows& rows, const std::optional<ProbeRow>& last, RowField field);

}  // namespace jetshell
