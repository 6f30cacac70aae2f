// Order statistics for Monte Carlo summaries (Algers 2018's percentile method, §3.6).
#pragma once

#include <vector>

namespace calibench {

// The q-quantile (q in [0, 1]) of the finite values, linear interpolation between order
// statistics (Hyndman & Fan type 7, numpy's default). NaN when there is no finite value.
double Quantile(std::vector<double> values, double q);
inline double Median(const std::vector<double>& values) { return Quantile(values, 0.5); }

}  // namespace calibench
