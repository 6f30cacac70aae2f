// schema.json: what the files of a run directory hold, written beside them (run_dir.h) so that a
// reader (the report, python/calibench_report) needs no list of its own. One JSON object:
//   naming_rule  the rule every column follows (metrics/metric_table.h), one string per point;
//   quantities   the quantities of a run (run_row.h RunQuantities: the metric table and the
//                method types' declared outputs): per quantity its name (unit included), unit,
//                label, doc, its columns (value, error, std, crlb), integer, tracked, how
//                summary.csv summarises it (summary: null | "statistics" | "with_rmse", and
//                the `metric` value it has there), ranked (methods are compared on it), target
//                (Algers 2018's bound on the 97.5th percentile of |error|, or null), headline
//                (the report's first page answers on it) and projection (null, or "error" /
//                "ratio": the report's section on the projection error reads it);
//   files        per CSV file its columns in file order: name, unit ("" when dimensionless), doc;
//   sweeps       per swept scenario (SweepPoint::sweep, in config order): its name, the role the
//                report gives it (scenario field report.role; "" when none), detections (oracle |
//                rendered), the swept fields, points, trials and whether it tracks (truth
//                changes);
//   methods      per registered method type (registry order): its name (type), the outputs it
//                declares (their quantities are in `quantities`) and its windup law (null, or
//                the option holding the exponent and the options that must be 0 for the law:
//                methods/method.h WindupLaw).
// It depends on the configuration alone: shards and their merge write the same file.
#pragma once

#include <string>

#include "bench/config/config_io.h"

namespace calibench {

std::string SchemaJson(const RunConfig& config);

}  // namespace calibench
