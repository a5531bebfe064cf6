// bench_support.hpp: what every benchmark program shares: robust statistics of repeated timings,
// the command line (--quick, --json and the shared parser), numbers written the same in every
// locale, and writing the JSON result. Benchmarks quote medians (the machines are shared:
// single runs can be several times slow) and ratios against a baseline measured in the same run.
#pragma once

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstddef>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>
#include <system_error>
#include <vector>

#include "bemsurg/number_text.hpp"
#include "bemsurg/timing.hpp"
#include "options/option_parser.hpp"

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

/// A benchmark's command line (src/options/option_parser.hpp): every benchmark takes --quick (the
/// seconds-long smoke run ctest runs) and --json PATH; the caller declares the rest and parses
/// with cli::parse_command_line. Called first in main, it also makes std::cout and std::cerr,
/// where the figures are printed, write numbers the same in every locale (number_text.hpp).
inline cli::OptionParser command_line(const std::string& program, const std::string& what, bool& quick, std::string& json_path) {
  use_classic_locale(std::cout);
  use_classic_locale(std::cerr);
  cli::OptionParser parser(program, "usage: " + program + " [options]\n\n" + what);
  parser.flag("--quick", quick, "a seconds-long smoke run (what ctest runs)");
  parser.value("--json", "PATH", json_path, "write the results to PATH as JSON");
  return parser;
}

/// x with `digits` digits after the point and always a sign ("%+.*f" without the locale): the
/// differences the tables print.
inline std::string signed_fixed_text(double x, int digits) { return (std::signbit(x) ? "" : "+") + fixed_text(x, digits); }

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
