// src/options/option_parser.hpp: the one command-line parser of bemsurg's programs: the `bemsurg`
// commands (src/cli), the benchmarks (benchmarks/) and the viewer (examples/viewer/main.cpp).
// A program's edge, not the library's API: it is not installed; the programs reach it through
// the build's `bemsurg_option_parser` target (CMakeLists.txt).
//
// Why one: each program had its own loop over argv, read numbers with std::stod/stoi/atof (which
// follow the C locale: under de_DE "0.25" is read as 0 or refused) and said different things about
// the same mistake. Here an option is declared once, bound to the variable it sets, with its help
// text and the default --help shows; numbers are read by parse_number (<charconv>, the same in
// every locale: include/bemsurg/number_text.hpp), and every error names the program, the option
// and the text ("cut: --gap: expected a number, got '0,1'"); an unknown option is answered with
// the list of known ones. tests/test_option_parser.cpp and tests/test_cli_locale.cpp check it.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <functional>
#include <iostream>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include "bemsurg/error.hpp"
#include "bemsurg/number_text.hpp"

namespace bemsurg::cli {

/// A command line that cannot be understood: unknown option, missing or bad value, extra argument.
class UsageError : public Error {
 public:
  using Error::Error;
};

/// "5,9,14" -> {5, 9, 14}, each item read by parse_number<T>; nothing when any item is empty or
/// not a T (so "5,,9", "5," and "" are refused).
template <typename T>
std::optional<std::vector<T>> parse_number_list(std::string_view text) {
  std::vector<T> out;
  for (;;) {
    const std::size_t comma = text.find(',');
    const std::optional<T> x = parse_number<T>(text.substr(0, comma));
    if (!x) return std::nullopt;
    out.push_back(*x);
    if (comma == std::string_view::npos) return out;
    text.remove_prefix(comma + 1);
  }
}

/// The numbers an option accepts beyond its type: from `min` to `max`, `min` itself excluded when
/// `above`. Applied to each item of a list.
struct ValueRange {
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
  bool above = false;

  bool contains(double x) const { return (above ? x > min : x >= min) && x <= max; }
  /// " from 1 to 99", " >= 4", " > 0" or "" (unbounded): what follows "a number" in a message.
  std::string text(bool integral) const {
    const auto bound = [integral](double x) { return integral ? std::to_string(static_cast<long long>(x)) : number_text(x); };
    const bool low = std::isfinite(min), high = std::isfinite(max);
    if (low && high && !above) return " from " + bound(min) + " to " + bound(max);
    std::string s;
    if (low) s += (above ? " > " : " >= ") + bound(min);
    if (high) s += std::string(low ? " and" : "") + " <= " + bound(max);
    return s;
  }
};

class OptionParser {
 public:
  /// `program` starts every message ("cut", "bench_cut", "bemsurg-viewer"); `usage` is printed by
  /// --help above the list of options (the usage line and what the program does).
  OptionParser(std::string program, std::string usage) : program_(std::move(program)), usage_(std::move(usage)) {}

  /// An option without a value ("-q, --quiet": a short and a long name, or one name) that sets
  /// `target` to true.
  OptionParser& flag(const std::string& names, bool& target, std::string help) {
    Option& o = add(names, "", std::move(help));
    o.read = [&target](std::string_view, const ValueRange&) { target = true; };
    return *this;
  }

  /// An option with a value (VALUE_NAME in --help and in messages), read into `target`: a
  /// std::string, a number (parse_number: a double must be finite) or a std::vector of numbers
  /// written "1,2,3". `target`'s value now is the default --help shows (none for an empty string
  /// or list; default_text() says it in words). A repeated option: the last one counts.
  template <typename T>
  OptionParser& value(const std::string& names, std::string value_name, T& target, std::string help) {
    Option& o = add(names, std::move(value_name), std::move(help));
    o.default_text = shown(target);
    o.read = [&target](std::string_view text, const ValueRange& range) { target = read_as<T>(text, range); };
    return *this;
  }

  /// An option whose value `read` interprets (a vector "X,Y,Z", a size "WxH", a method's name).
  /// `read` throws std::invalid_argument with what it expected ("three comma-separated numbers");
  /// the message then names the program, the option and the text. Called once per occurrence.
  OptionParser& custom_value(const std::string& names, std::string value_name, std::string help,
                             std::function<void(const std::string&)> read) {
    Option& o = add(names, std::move(value_name), std::move(help));
    o.read = [read = std::move(read)](std::string_view text, const ValueRange&) { read(std::string(text)); };
    return *this;
  }

  /// The one argument without a dash (the scene file); a second one is refused with `extra_hint`
  /// ("one scene file per run"). A lone "-" counts as an argument, not an option.
  OptionParser& positional(std::string value_name, std::string& target, std::string extra_hint) {
    Option o;
    o.value_name = std::move(value_name);
    o.help = std::move(extra_hint);
    o.positional = true;
    o.read = [&target](std::string_view text, const ValueRange&) { target = std::string(text); };
    options_.push_back(std::move(o));
    return *this;
  }

  // Modifiers of the option declared last.
  /// Missing from the command line: "<program>: missing --steps K" (in declaration order).
  OptionParser& required() {
    last().required = true;
    return *this;
  }
  /// The default --help shows, in words ("0.1 x the local edge length", "9,14; --quick: 5").
  OptionParser& default_text(std::string text) {
    last().default_text = std::move(text);
    return *this;
  }
  /// Numbers from `min` to `max` only (each item of a list).
  OptionParser& between(double min, double max) {
    last().range = {min, max, false};
    return *this;
  }
  OptionParser& at_least(double min) { return between(min, std::numeric_limits<double>::infinity()); }
  /// Numbers greater than `min` only.
  OptionParser& above(double min) {
    last().range = {min, std::numeric_limits<double>::infinity(), true};
    return *this;
  }

  /// Reads argv[1..argc-1] in order into the bound variables. Returns false at -h or --help (the
  /// caller prints help() and exits 0; what follows is not read); throws UsageError for an unknown
  /// option, a missing or bad value, an extra argument or a missing required one. "--name=VALUE"
  /// is "--name VALUE"; a value may start with a dash ("--at -1,0,0").
  bool parse(int argc, const char* const* argv) {
    for (Option& o : options_) o.given = false;
    for (int i = 1; i < argc; ++i) {
      const std::string_view arg = argv[i];
      if (arg == "-h" || arg == "--help") return false;
      if (arg.size() < 2 || arg[0] != '-') {
        read_positional(arg);
        continue;
      }
      const std::size_t equals = arg.rfind("--", 0) == 0 ? arg.find('=') : std::string_view::npos;
      const std::string name(arg.substr(0, equals));
      Option& o = find(name);
      if (o.value_name.empty()) {
        if (equals != std::string_view::npos) fail(name + " takes no value, got '" + std::string(arg) + "'");
        o.read("", o.range);
      } else if (equals != std::string_view::npos) {
        read_value(o, name, arg.substr(equals + 1));
      } else {
        read_value(o, name, i + 1 < argc ? argv[++i] : "");
      }
      o.given = true;
    }
    for (const Option& o : options_)
      if (o.required && !o.given) fail("missing " + (o.positional ? o.value_name : o.names.front() + " " + o.value_name));
    return true;
  }

  /// Whether the option (any of its names) was on the command line of the last parse().
  bool given(const std::string& name) const {
    for (const Option& o : options_)
      if (std::find(o.names.begin(), o.names.end(), name) != o.names.end()) return o.given;
    throw std::logic_error("OptionParser::given: no option " + name);
  }

  const std::string& program() const { return program_; }

  /// The usage, then every option with its value, help, and its default or "(required)".
  std::string help() const {
    std::vector<std::pair<std::string, std::string>> rows;
    for (const Option& o : options_) {
      if (o.positional) continue;
      std::string left = "  ";
      for (std::size_t k = 0; k < o.names.size(); ++k) left += (k ? ", " : "") + o.names[k];
      if (!o.value_name.empty()) left += " " + o.value_name;
      std::string right = o.help;
      if (o.required)
        right += " (required)";
      else if (!o.default_text.empty())
        right += " (default: " + o.default_text + ")";
      rows.emplace_back(std::move(left), std::move(right));
    }
    rows.emplace_back("  -h, --help", "show this help");
    std::size_t column = 0;
    for (const auto& row : rows) column = std::max(column, std::min<std::size_t>(row.first.size(), kWidestName));
    column += 2;
    std::string out = usage_;
    if (!out.empty() && out.back() != '\n') out += '\n';
    out += "\noptions:\n";
    for (const auto& [left, right] : rows) {
      out += left;
      // A long name puts its help on the next line; every help line starts at `column`.
      out += left.size() + 2 > column ? "\n" + std::string(column, ' ') : std::string(column - left.size(), ' ');
      for (char c : right) out += c == '\n' ? "\n" + std::string(column, ' ') : std::string(1, c);
      out += '\n';
    }
    return out;
  }

 private:
  static constexpr std::size_t kWidestName = 30;  // wider names put their help on the next line

  struct Option {
    std::vector<std::string> names;  // "-q", "--quiet"
    std::string value_name;          // "" for a flag
    std::string help, default_text;
    ValueRange range;
    bool required = false, positional = false, given = false;
    std::function<void(std::string_view, const ValueRange&)> read;
  };

  template <typename T>
  static std::string shown(const T& value) {
    if constexpr (std::is_same_v<T, std::string>) {
      return value;
    } else if constexpr (std::is_arithmetic_v<T>) {
      if constexpr (std::is_integral_v<T>)
        return std::to_string(value);
      else
        return number_text(value);
    } else {
      std::string s;
      for (const auto& x : value) s += (s.empty() ? "" : ",") + shown(x);
      return s;
    }
  }

  /// `x` when it is a number (finite, for a floating type) in `range`; else throws what was
  /// expected ("a whole number from 1 to 99").
  template <typename N>
  static N checked(const std::optional<N>& x, const ValueRange& range, const std::string& kind) {
    bool ok = x.has_value();
    if constexpr (std::is_floating_point_v<N>) ok = ok && std::isfinite(*x);
    if (!ok || !range.contains(static_cast<double>(*x))) throw std::invalid_argument(kind + range.text(std::is_integral_v<N>));
    return *x;
  }

  template <typename T>
  static T read_as(std::string_view text, const ValueRange& range) {
    if constexpr (std::is_same_v<T, std::string>) {
      return std::string(text);
    } else if constexpr (std::is_arithmetic_v<T>) {
      return checked(parse_number<T>(text), range, std::is_integral_v<T> ? "a whole number" : "a number");
    } else {
      using N = typename T::value_type;
      const std::string kind = std::is_integral_v<N> ? "comma-separated whole numbers" : "comma-separated numbers";
      const std::optional<std::vector<N>> items = parse_number_list<N>(text);
      if (!items) throw std::invalid_argument(kind + range.text(std::is_integral_v<N>));
      for (const N& x : *items) checked<N>(x, range, kind);
      return T(items->begin(), items->end());
    }
  }

  [[noreturn]] void fail(const std::string& message) const { throw UsageError(program_ + ": " + message); }

  Option& add(const std::string& names, std::string value_name, std::string help) {
    Option o;
    for (std::size_t start = 0; start <= names.size();) {
      const std::size_t comma = std::min(names.find(',', start), names.size());
      std::string name = names.substr(start, comma - start);
      name.erase(0, name.find_first_not_of(' '));
      name.erase(name.find_last_not_of(' ') + 1);
      if (name.size() < 2 || name[0] != '-') throw std::logic_error("OptionParser: bad option name '" + name + "'");
      o.names.push_back(std::move(name));
      start = comma + 1;
    }
    o.value_name = std::move(value_name);
    o.help = std::move(help);
    options_.push_back(std::move(o));
    return options_.back();
  }

  Option& last() {
    if (options_.empty()) throw std::logic_error("OptionParser: a modifier before any option");
    return options_.back();
  }

  Option& find(const std::string& name) {
    for (Option& o : options_)
      if (std::find(o.names.begin(), o.names.end(), name) != o.names.end()) return o;
    std::string known;
    for (const Option& o : options_)
      if (!o.positional) known += o.names.back() + ", ";
    fail("unknown option '" + name + "' (known: " + known + "--help)");
  }

  void read_value(Option& o, const std::string& name, std::string_view text) {
    // An empty value ("--output=", "") names no file and no number: as if it were missing.
    if (text.empty()) fail(name + " needs a value (" + name + " " + o.value_name + ")");
    try {
      o.read(text, o.range);
    } catch (const std::invalid_argument& e) { fail(name + ": expected " + e.what() + ", got '" + std::string(text) + "'"); }
  }

  void read_positional(std::string_view arg) {
    for (Option& o : options_)
      if (o.positional) {
        if (o.given) fail("unexpected argument '" + std::string(arg) + "' (" + o.help + ")");
        o.read(arg, o.range);
        o.given = true;
        return;
      }
    fail("unexpected argument '" + std::string(arg) + "'");
  }

  std::string program_, usage_;
  std::vector<Option> options_;
};

/// For a program's main: parses the command line and runs `check` (further conditions between
/// options, throwing UsageError). Returns nothing when the program goes on; else the status to
/// exit with: 0 after --help (the help printed on stdout), 2 after a usage error (the message and
/// a pointer to --help on stderr).
inline std::optional<int> parse_command_line(OptionParser& parser, int argc, const char* const* argv,
                                             const std::function<void()>& check = {}) {
  try {
    if (!parser.parse(argc, argv)) {
      std::cout << parser.help();
      return 0;
    }
    if (check) check();
    return std::nullopt;
  } catch (const UsageError& e) {
    std::cerr << e.what() << "\nRun '" << parser.program() << " --help' for the options.\n";
    return 2;
  }
}

}  // namespace bemsurg::cli
