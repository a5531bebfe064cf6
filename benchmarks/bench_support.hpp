// bench_support.hpp: what every benchmark program shares: robust statistics of repeated timings,
// the --sizes list, and writing the JSON result. Benchmarks quote medians (the machines are shared:
// single runs can be several times slow) and ratios against a baseline measured in the same run.
#pragma once

#include <algorithm>
#include <cstddef>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "bemsurg/timing.hpp"

namespace bemsurg::bench {

using Clock = SteadyClock;

/// The median (mean of the two middle values for an even count); 0 for no values.
inline double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const std::size_t m = v.size() / 2;
  return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

/// Tail statistics of many short timings (haptic updates).
struct Percentiles {
  double median = 0, p99 = 0, p999 = 0, max = 0;
};
inline Percentiles percentiles(std::vector<double> v) {
  if (v.empty()) return {};
  std::sort(v.begin(), v.end());
  auto at = [&](double q) { return v[std::min(v.size() - 1, static_cast<std::size_t>(q * double(v.size())))]; };
  return {at(0.5), at(0.99), at(0.999), v.back()};
}

/// "5,9,14" -> {5, 9, 14}; throws std::invalid_argument on anything else.
inline std::vector<int> parse_int_list(const std::string& text) {
  std::vector<int> out;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    std::size_t used = 0;
    out.push_back(std::stoi(item, &used));
    if (used != item.size()) throw std::invalid_argument("not an integer: '" + item + "'");
  }
  return out;
}

/// Writes the result as indented JSON; false (with a message naming the program) when it cannot.
inline bool write_json_file(const std::string& path, const nlohmann::json& result, const char* program) {
  if (path.empty()) return true;
  std::ofstream out(path);
  out << result.dump(2) << "\n";
  if (!out) {
    std::cerr << program << ": cannot write " << path << "\n";
    return false;
  }
  return true;
}

}  // namespace bemsurg::bench
