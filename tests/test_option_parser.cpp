// The one command-line parser of bemsurg's programs (src/options/option_parser.hpp): the `bemsurg`
// commands, the benchmarks and the viewer declare their options with it, so what it accepts and
// how it refuses is their contract (docs/cli.md: a command line that cannot be understood exits
// with 2 and says why). Each refusal names the program, the option and the text.
#include <catch2/catch.hpp>

#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "options/option_parser.hpp"

using bemsurg::cli::OptionParser;
using bemsurg::cli::UsageError;

namespace {

/// The options of a small program, bound to its fields.
struct ToyOptions {
  std::string scene, output, table;
  double gap = 0.1;
  int steps = 3;
  std::vector<int> sizes{5, 9};
  bool quiet = false;
};

OptionParser toy_parser(ToyOptions& o) {
  OptionParser parser("toy", "usage: toy SCENE.json -o OUTDIR [options]\n\nA program to test the parser.\n");
  parser.positional("SCENE.json", o.scene, "one scene file per run").required();
  parser.value("-o, --output", "OUTDIR", o.output, "output directory").required();
  parser.value("--gap", "W", o.gap, "gap width").above(0.0);
  parser.value("--steps", "K", o.steps, "cut steps").between(1, 99);
  parser.value("--sizes", "N1,N2,...", o.sizes, "box sizes").at_least(2);
  parser.value("--table", "FILE", o.table, "table file\nsecond line of its help");
  parser.flag("-q, --quiet", o.quiet, "print nothing");
  return parser;
}

bool parse_args(OptionParser& parser, std::vector<const char*> args) {
  args.insert(args.begin(), "toy");
  return parser.parse(static_cast<int>(args.size()), args.data());
}

}  // namespace

TEST_CASE("the option parser reads values, flags and the argument into the bound variables", "[cli][options]") {
  ToyOptions o;
  OptionParser parser = toy_parser(o);
  REQUIRE(parse_args(parser, {"scene.json", "-o", "out", "--gap", "0.5", "--steps", "7", "--sizes", "4,8,16", "-q", "--table=t.bin"}));
  CHECK(o.scene == "scene.json");
  CHECK(o.output == "out");
  CHECK(o.gap == 0.5);
  CHECK(o.steps == 7);
  CHECK(o.sizes == std::vector<int>{4, 8, 16});
  CHECK(o.quiet);
  CHECK(o.table == "t.bin");
  CHECK(parser.given("--gap"));
  CHECK(parser.given("-q"));

  // Untouched options keep their defaults; the last of a repeated option counts; a value may
  // start with a dash, "--name=value" is "--name value", "+2" is 2.
  ToyOptions d;
  OptionParser again = toy_parser(d);
  REQUIRE(parse_args(again, {"--output=a", "--output", "-dir", "s.json", "--steps", "+2", "--steps", "5"}));
  CHECK(d.output == "-dir");
  CHECK(d.steps == 5);
  CHECK(d.gap == 0.1);
  CHECK(d.sizes == std::vector<int>{5, 9});
  CHECK_FALSE(d.quiet);
  CHECK_FALSE(again.given("--gap"));
}

TEST_CASE("the option parser refuses an unknown option and lists the known ones", "[cli][options]") {
  ToyOptions o;
  OptionParser parser = toy_parser(o);
  CHECK_THROWS_AS(parse_args(parser, {"s.json", "-o", "out", "--fast"}), UsageError);
  CHECK_THROWS_WITH(parse_args(parser, {"s.json", "-o", "out", "--fast"}),
                    "toy: unknown option '--fast' (known: --output, --gap, --steps, --sizes, --table, --quiet, --help)");
  CHECK_THROWS_WITH(parse_args(parser, {"s.json", "-x"}), Catch::StartsWith("toy: unknown option '-x'"));
  CHECK_THROWS_WITH(parse_args(parser, {"s.json", "--gapp=1"}), Catch::StartsWith("toy: unknown option '--gapp'"));
}

TEST_CASE("the option parser refuses a missing value, a missing required option and an extra argument", "[cli][options]") {
  ToyOptions o;
  OptionParser parser = toy_parser(o);
  CHECK_THROWS_WITH(parse_args(parser, {"s.json", "-o"}), "toy: -o needs a value (-o OUTDIR)");
  CHECK_THROWS_WITH(parse_args(parser, {"s.json", "--output="}), "toy: --output needs a value (--output OUTDIR)");
  CHECK_THROWS_WITH(parse_args(parser, {"s.json", "-o", "out", "--gap"}), "toy: --gap needs a value (--gap W)");
  CHECK_THROWS_WITH(parse_args(parser, {"s.json"}), "toy: missing -o OUTDIR");
  CHECK_THROWS_WITH(parse_args(parser, {"-o", "out"}), "toy: missing SCENE.json");
  CHECK_THROWS_WITH(parse_args(parser, {"a.json", "b.json", "-o", "out"}), "toy: unexpected argument 'b.json' (one scene file per run)");
  CHECK_THROWS_WITH(parse_args(parser, {"s.json", "-o", "out", "--quiet=yes"}), "toy: --quiet takes no value, got '--quiet=yes'");
}

TEST_CASE("the option parser refuses a bad number naming the option and the text", "[cli][options]") {
  ToyOptions o;
  OptionParser parser = toy_parser(o);
  const auto refused = [&](std::vector<const char*> extra) {
    std::vector<const char*> args{"s.json", "-o", "out"};
    args.insert(args.end(), extra.begin(), extra.end());
    try {
      parse_args(parser, args);
    } catch (const UsageError& e) { return std::string(e.what()); }
    return std::string("accepted");
  };
  CHECK(refused({"--gap", "0,1"}) == "toy: --gap: expected a number > 0, got '0,1'");
  CHECK(refused({"--gap", "0.1x"}) == "toy: --gap: expected a number > 0, got '0.1x'");
  CHECK(refused({"--gap", "inf"}) == "toy: --gap: expected a number > 0, got 'inf'");
  CHECK(refused({"--gap", "nan"}) == "toy: --gap: expected a number > 0, got 'nan'");
  CHECK(refused({"--gap", "0"}) == "toy: --gap: expected a number > 0, got '0'");
  CHECK(refused({"--gap", "1e400"}) == "toy: --gap: expected a number > 0, got '1e400'");
  CHECK(refused({"--steps", "2.5"}) == "toy: --steps: expected a whole number from 1 to 99, got '2.5'");
  CHECK(refused({"--steps", "100"}) == "toy: --steps: expected a whole number from 1 to 99, got '100'");
  CHECK(refused({"--steps", " 5"}) == "toy: --steps: expected a whole number from 1 to 99, got ' 5'");
  CHECK(refused({"--steps", "99999999999"}) == "toy: --steps: expected a whole number from 1 to 99, got '99999999999'");
  CHECK(refused({"--sizes", "4,,8"}) == "toy: --sizes: expected comma-separated whole numbers >= 2, got '4,,8'");
  CHECK(refused({"--sizes", "4,1"}) == "toy: --sizes: expected comma-separated whole numbers >= 2, got '4,1'");
  CHECK(refused({"--sizes", "4,"}) == "toy: --sizes: expected comma-separated whole numbers >= 2, got '4,'");
  CHECK(refused({"--gap", "1e-3", "--steps", "99", "--sizes", "2"}) == "accepted");
}

TEST_CASE("the option parser reads custom values and stops at --help", "[cli][options]") {
  int width = 0, height = 0;
  std::string scene = "none";
  OptionParser parser("viewer", "usage: viewer");
  parser.custom_value("--size", "WxH", "picture size", [&](const std::string& text) {
    const auto x = text.find('x');
    const auto w = bemsurg::parse_number<int>(text.substr(0, x)), h = bemsurg::parse_number<int>(text.substr(x + 1));
    if (x == std::string::npos || !w || !h) throw std::invalid_argument("WxH");
    width = *w;
    height = *h;
  });
  parser.value("--scene", "FILE", scene, "scene");
  REQUIRE(parse_args(parser, {"--size", "640x480"}));
  CHECK(width == 640);
  CHECK(height == 480);
  CHECK_THROWS_WITH(parse_args(parser, {"--size", "640"}), "viewer: --size: expected WxH, got '640'");
  // --help ends the reading: nothing after it is read or refused.
  CHECK_FALSE(parse_args(parser, {"--scene", "a.json", "-h", "--bogus", "--scene", "b.json"}));
  CHECK(scene == "a.json");
  CHECK_FALSE(parse_args(parser, {"--help"}));
}

TEST_CASE("the option parser's help lists every option with its value, its default or required, and --help", "[cli][options]") {
  ToyOptions o;
  OptionParser parser = toy_parser(o);
  parser.value("--update", "METHOD", o.table, "update method").default_text("exact");
  const std::string help = parser.help();
  INFO(help);
  CHECK_THAT(help, Catch::StartsWith("usage: toy SCENE.json -o OUTDIR [options]\n\nA program to test the parser.\n\noptions:\n"));
  CHECK_THAT(help, Catch::Contains("  -o, --output OUTDIR  output directory (required)\n"));
  CHECK_THAT(help, Catch::Contains("  --gap W              gap width (default: 0.1)\n"));
  CHECK_THAT(help, Catch::Contains("  --steps K            cut steps (default: 3)\n"));
  CHECK_THAT(help, Catch::Contains("  --sizes N1,N2,...    box sizes (default: 5,9)\n"));
  CHECK_THAT(help, Catch::Contains("  --table FILE         table file\n                       second line of its help\n"));
  CHECK_THAT(help, Catch::Contains("  -q, --quiet          print nothing\n"));
  CHECK_THAT(help, Catch::Contains("  --update METHOD      update method (default: exact)\n"));
  CHECK_THAT(help, Catch::EndsWith("  -h, --help           show this help\n"));
}

TEST_CASE("parse_command_line exits 0 after --help and 2 after a usage error or a failed check", "[cli][options]") {
  ToyOptions o;
  OptionParser parser = toy_parser(o);
  auto run = [&](std::vector<const char*> args, const std::function<void()>& check = {}) {
    args.insert(args.begin(), "toy");
    return bemsurg::cli::parse_command_line(parser, static_cast<int>(args.size()), args.data(), check);
  };
  CHECK(run({"--help"}) == 0);
  CHECK(run({"s.json", "--bogus"}) == 2);
  CHECK(run({"s.json", "-o", "out"}) == std::nullopt);
  CHECK(run({"s.json", "-o", "out"}, [] { throw UsageError("toy: --gap and --steps do not go together"); }) == 2);
}
