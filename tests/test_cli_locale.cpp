// The command line's numbers under a comma-decimal locale (docs/cli.md; include/bemsurg/number_text.hpp
// says why): an application that embeds bemsurg's option parser, or a later `bemsurg` that calls
// setlocale(LC_ALL, ""), must still read "--gap 0.25" as 0.25, refuse "0,25" naming the option,
// and write its numbers with a point. The parser and parse_vector3 are header code of the programs
// (src/options/option_parser.hpp, src/cli/commands.hpp), so they are checked here in-process with
// de_DE.UTF-8 set as both the C and the C++ global locale. The `bemsurg` binary itself never calls
// setlocale: running it under LC_ALL=de_DE.UTF-8 (the last case) guards what it writes against a
// future change, it cannot fail today. Before the parser, parse_vector3 used std::stod, which under
// this locale stops at the point: the code before this change refused "0.01,-0.02,0.05" (the
// parse_vector3 check of the first case failed there).
#include <catch2/catch.hpp>

#include <sys/wait.h>

#include <algorithm>
#include <clocale>
#include <cstdlib>
#include <fstream>
#include <locale>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "cli/commands.hpp"
#include "options/option_parser.hpp"
#include "support/skip.hpp"
#include "support/temp_dir.hpp"

namespace {

constexpr const char* kCommaLocale = "de_DE.UTF-8";

/// Sets de_DE.UTF-8 as the C locale (setlocale: strtod, printf, to_string) and as the C++ global
/// locale (streams created afterwards) for its lifetime and restores both. Skips the test case
/// (exit 77, tests/support/skip.hpp) where the machine has no such locale.
class CommaDecimalLocale {
 public:
  CommaDecimalLocale() : saved_cpp_(std::locale()) {
    const char* c = std::setlocale(LC_ALL, nullptr);
    saved_c_ = c ? c : "C";
    bool available = std::setlocale(LC_ALL, kCommaLocale) != nullptr;
    if (available) {
      try {
        std::locale::global(std::locale(kCommaLocale));
      } catch (const std::runtime_error&) { available = false; }
    }
    if (!available) std::setlocale(LC_ALL, saved_c_.c_str());
    bemsurg::testing::skip_unless(available, "no de_DE.UTF-8 locale on this machine (Debian: locales, locale-gen de_DE.UTF-8)");
  }
  ~CommaDecimalLocale() {
    std::locale::global(saved_cpp_);
    std::setlocale(LC_ALL, saved_c_.c_str());
  }
  CommaDecimalLocale(const CommaDecimalLocale&) = delete;
  CommaDecimalLocale& operator=(const CommaDecimalLocale&) = delete;

 private:
  std::locale saved_cpp_;
  std::string saved_c_;
};

/// Parses `args` (after a program name) with `parser`.
bool parse(bemsurg::cli::OptionParser& parser, std::vector<const char*> args) {
  args.insert(args.begin(), "prog");
  return parser.parse(static_cast<int>(args.size()), args.data());
}

}  // namespace

TEST_CASE("under a comma-decimal locale the command line reads 0.25 as 0.25 and refuses 0,25 naming the option", "[cli][locale]") {
  const CommaDecimalLocale locale;
  REQUIRE(std::string(std::localeconv()->decimal_point) == ",");  // the hazard is real in this process

  double gap = 0.0;
  int steps = 0;
  std::vector<double> weights;
  bemsurg::cli::OptionParser parser("cut", "usage: cut");
  parser.value("--gap", "W", gap, "gap width").above(0.0);
  parser.value("--steps", "K", steps, "steps");
  parser.value("--weights", "W1,W2", weights, "weights");
  REQUIRE(parse(parser, {"--gap", "0.25", "--steps", "1000", "--weights", "0.5,-1.5e-3"}));
  CHECK(gap == 0.25);
  CHECK(steps == 1000);
  CHECK(weights == std::vector<double>{0.5, -1.5e-3});
  CHECK_THROWS_WITH(parse(parser, {"--gap", "0,25"}), "cut: --gap: expected a number > 0, got '0,25'");
  CHECK_THROWS_WITH(parse(parser, {"--steps", "1.000"}), "cut: --steps: expected a whole number, got '1.000'");

  // The commands' X,Y,Z options (press --at, --direction; cut --from, --direction).
  const Eigen::Vector3d at = bemsurg::cli::parse_vector3("press", "--at", "0.01,-0.02,0.05");
  CHECK(at == Eigen::Vector3d(0.01, -0.02, 0.05));
  CHECK_THROWS_WITH(bemsurg::cli::parse_vector3("press", "--at", "0,01;0,02;0,05"),
                    Catch::Contains("press: --at") && Catch::Contains("'0,01;0,02;0,05'"));
}

TEST_CASE("under a comma-decimal locale --help writes the defaults with a point and no digit grouping", "[cli][locale]") {
  const CommaDecimalLocale locale;
  double tolerance = 1e-8, spin = 0.25;
  int repeats = 10000;
  std::vector<int> sizes{1584, 4752};
  bemsurg::cli::OptionParser parser("bench", "usage: bench [options]");
  parser.value("--tolerance", "T", tolerance, "relative residual");
  parser.value("--spin-us", "US", spin, "spin");
  parser.value("--repeats", "R", repeats, "repeats");
  parser.value("--sizes", "N1,N2", sizes, "sizes");
  const std::string help = parser.help();
  INFO(help);
  CHECK_THAT(help, Catch::Contains("(default: 1e-08)") && Catch::Contains("(default: 0.25)") && Catch::Contains("(default: 10000)") &&
                       Catch::Contains("(default: 1584,4752)"));
  CHECK(help.find("0,25") == std::string::npos);
}

TEST_CASE("bemsurg press run under LC_ALL=de_DE.UTF-8 reads --depth 0.001 and writes its numbers with a point", "[cli][locale]") {
  {
    const CommaDecimalLocale locale;  // skip where the environment's locale would not exist either
  }
  const bemsurg_test::TempDir dir("bemsurg_test_cli_locale_");
  const std::string scene = dir.write("scene.json", R"({
    "mesh": {"generator": "box", "min": [-0.05, -0.05, 0], "max": [0.05, 0.05, 0.05], "divisions": [2, 2, 1]},
    "material": {"young_modulus": 3000, "poisson_ratio": 0.45, "density": 0},
    "boundary_conditions": {"rules": [{"select": {"plane": {"point": [0, 0, 0], "normal": [0, 0, 1]}},
                                       "displacement": [0, 0, 0]}]}})");
  const std::string out = dir.file("out"), log = dir.file("log.txt");
  const std::string command = std::string("LC_ALL=") + kCommaLocale + " '" + BEMSURG_CLI_PATH + "' press '" + scene +
                              "' --tool point --at 0.01,0.01,0.05 --direction 0,0,-1 --depth 0.001 -o '" + out + "' >'" + log + "' 2>&1";
  const int status = std::system(command.c_str());
  std::ifstream log_in(log);
  std::stringstream printed;
  printed << log_in.rdbuf();
  INFO(printed.str());
  REQUIRE(WIFEXITED(status));
  REQUIRE(WEXITSTATUS(status) == 0);
  CHECK_THAT(printed.str(), Catch::Contains("depth 0.001: force ("));
  std::ifstream force_in(out + "/force.json");
  const nlohmann::json force = nlohmann::json::parse(force_in);
  CHECK(force.at("depth").get<double>() == 0.001);
  CHECK(force.at("tool") == "point");
  // elements.csv: 14 comma-separated fields per row, so a decimal comma would add fields.
  std::ifstream csv(out + "/elements.csv");
  std::string header, row;
  REQUIRE(std::getline(csv, header));
  REQUIRE(std::getline(csv, row));
  CHECK(std::count(row.begin(), row.end(), ',') == 13);
  CHECK(row.find('.') != std::string::npos);
}
