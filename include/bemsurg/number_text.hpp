// bemsurg/number_text.hpp: numbers to and from text, the same in every locale.
//
// Why: std::strtod, std::stod, printf("%g"), std::to_string(double) and streams imbued with the
// global locale all follow the locale an application sets. A Qt application (3D Slicer, most
// surgical simulators) calls setlocale(LC_ALL, "") at start-up; in a comma-decimal locale
// (de_DE, fr_FR) strtod then reads "0.45" as 0 and stops at the dot, silently, and
// to_string(0.45) writes "0,450000". <charconv> ignores the locale by definition
// ([charconv.syn]), so every number bemsurg reads from or writes to text goes through here.
// tests/test_locale.cpp checks the whole path under de_DE.UTF-8 (docs/design.md, "Text and
// locale").
#pragma once

#include <charconv>
#include <cstddef>
#include <cstdint>
#include <locale>
#include <optional>
#include <ostream>
#include <string>
#include <string_view>
#include <system_error>
#include <type_traits>

namespace bemsurg {

/// Reads the whole of `text` as a number of type T (double, float or an integer type); nothing
/// else may follow. A leading '+' is accepted (from_chars rejects it, people write it). Returns
/// nothing for empty text, trailing characters, or a value out of T's range; the caller names
/// the key, line or element in its error. Never depends on the locale.
template <typename T>
std::optional<T> parse_number(std::string_view text) {
  static_assert(std::is_arithmetic_v<T> && !std::is_same_v<T, bool>, "parse_number: a number type");
  if (!text.empty() && text.front() == '+') {
    text.remove_prefix(1);
    if (text.empty() || text.front() == '+' || text.front() == '-') return std::nullopt;  // "++1", "+-1" are not numbers
  }
  T value{};
  const char* end = text.data() + text.size();
  const auto result = std::from_chars(text.data(), end, value);
  if (result.ec != std::errc() || result.ptr != end) return std::nullopt;
  return value;
}

/// Appends the shortest decimal text that reads back as exactly x ("0.45", "1e-07", "inf",
/// "nan"), never a comma: what every data file (CSV, JSON, VTK, OBJ) bemsurg writes uses.
inline void append_number(std::string& out, double x) {
  char buffer[32];  // the longest shortest-round-trip double is 24 characters
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, x);
  out.append(buffer, result.ptr);
}

/// Appends an integer in decimal, no grouping.
template <typename Integer, typename = std::enable_if_t<std::is_integral_v<Integer>>>
void append_integer(std::string& out, Integer x) {
  char buffer[24];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, x);
  out.append(buffer, result.ptr);
}

/// The shortest round-trip text of x: for messages and file names, instead of std::to_string
/// (which prints "%f" in the current locale and loses small values: to_string(1e-9) is "0.000000").
inline std::string number_text(double x) {
  std::string s;
  append_number(s, x);
  return s;
}

namespace detail {
/// to_chars with a precision, clamped to what a double can show; the shortest text when it fails.
inline std::string formatted_number(double x, std::chars_format format, int digits, int min_digits) {
  char buffer[352];  // DBL_MAX in fixed notation has 309 digits before the point
  const int precision = digits < min_digits ? min_digits : digits > 17 ? 17 : digits;
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, x, format, precision);
  if (result.ec != std::errc()) return number_text(x);
  return std::string(buffer, result.ptr);
}
}  // namespace detail

/// x with `digits` digits after the point ("%.*f" without the locale), for tables read by people.
inline std::string fixed_text(double x, int digits) { return detail::formatted_number(x, std::chars_format::fixed, digits, 0); }

/// x with `digits` significant digits ("%.*g" without the locale).
inline std::string general_text(double x, int digits) { return detail::formatted_number(x, std::chars_format::general, digits, 1); }

/// x in scientific notation with `digits` digits after the point ("%.*e" without the locale:
/// "1.234e-05"), for residuals and tolerances in messages and printed tables.
inline std::string scientific_text(double x, int digits) { return detail::formatted_number(x, std::chars_format::scientific, digits, 0); }

/// Makes a stream write and read numbers the same in every locale ("C": point, no grouping),
/// whatever std::locale::global() says. Call it on every stream that writes a file or a
/// report another program parses. Returns the stream for chaining.
template <typename Stream>
Stream& use_classic_locale(Stream& stream) {
  stream.imbue(std::locale::classic());
  return stream;
}

}  // namespace bemsurg
