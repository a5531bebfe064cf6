// The one checked reader of bemsurg's JSON inputs (scene files, action scripts): a value of a
// parsed document together with its key path ("boundary_conditions.rules[1].select.plane.normal"),
// so that every error names the key a user must fix (docs/scene-format.md, docs/actions.md).
//
// Private to the library (src/io/): nlohmann-json is a private dependency of bemsurg and stays out
// of the installed headers, so this header sees only its forward declarations and every access to
// the tree is compiled once, in json_reader.cpp. Numbers come from nlohmann's parser, which reads
// the same in every locale.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <initializer_list>
#include <memory>
#include <nlohmann/json_fwd.hpp>
#include <optional>
#include <string>
#include <vector>

namespace bemsurg::io {

/// Throws SceneError "<key>: <what>" (only <what> when `key` is empty): the form of every scene
/// error, also for checks made after the JSON was read (the CSV files, the remeshing request).
[[noreturn]] void fail_at(const std::string& key, const std::string& what);

/// x as JSON writes it ("1.0", "0.45", "1e-09"): how messages quote a value that was read from
/// JSON, so that the user recognises what was written. Independent of the locale.
std::string json_number_text(double x);

/// What every reader of one document shares: the name put in front of its messages (empty for
/// scene files, whose messages start with the key path; the file name for action scripts) and
/// where the warnings about unknown keys go.
struct JsonSource {
  std::string name;
  std::vector<std::string>* warnings = nullptr;
};

/// A parsed JSON text. Throws SceneError "<name>: not valid JSON: <parser's message, with line
/// and column>" when the text is not JSON.
class JsonDocument {
 public:
  JsonDocument(const std::string& text, const std::string& name);
  ~JsonDocument();
  JsonDocument(JsonDocument&&) noexcept;
  JsonDocument(const JsonDocument&) = delete;
  JsonDocument& operator=(const JsonDocument&) = delete;

  const nlohmann::json& root() const { return *root_; }

 private:
  std::unique_ptr<nlohmann::json> root_;
};

/// One value of a document and its key path. Cheap to copy; it refers to the document and the
/// source, which must outlive it. Every check throws SceneError
/// "<source name>: <path>: <what>" (without the parts that are empty).
class JsonReader {
 public:
  JsonReader(const nlohmann::json& value, const JsonSource& source, std::string path = {});

  const std::string& path() const { return path_; }
  /// The path of a member or an element: "mesh" + "min" -> "mesh.min", "rules" + 1 -> "rules[1]".
  std::string path_of(const std::string& key) const;
  std::string path_of(std::size_t index) const;

  /// Throws SceneError at this value's path, or at another key of the same document.
  [[noreturn]] void fail(const std::string& what) const;
  [[noreturn]] void fail_at(const std::string& path, const std::string& what) const;
  /// Adds a warning about this value ("<path>: <what>").
  void warn(const std::string& what) const;

  bool is_object() const;
  bool is_array() const;
  bool is_string() const;
  /// Members of an object, elements of an array (0 for anything else).
  std::size_t size() const;
  bool empty() const { return size() == 0; }
  /// "an object", "an array", "a string", "a boolean", "a number" or "null", for messages.
  std::string type_name() const;
  /// The value as JSON text, for messages ("got 3", "got [1, 2]").
  std::string dump() const;

  /// Throws "expected an object, got ..." unless this is an object; returns *this.
  const JsonReader& object() const;
  bool has(const std::string& key) const;
  /// The member `key`; throws "<path>.<key>: missing (required)" when absent.
  JsonReader required(const std::string& key) const;
  /// The member `key`, or nothing when absent.
  std::optional<JsonReader> optional(const std::string& key) const;
  /// Element `index` of an array (the caller has checked size()).
  JsonReader operator[](std::size_t index) const;
  /// The member names of an object, in the document's order (sorted by name).
  std::vector<std::string> keys() const;

  /// A finite number (an integer is a number).
  double number() const;
  /// A number > 0 ("must be positive, got ...").
  double positive() const;
  /// A number >= 0 ("must not be negative, got ...").
  double non_negative() const;
  /// An integer; 3.0 is accepted as 3, since JSON writers differ in how they print whole numbers.
  long long integer() const;
  /// An integer in [lo, hi] ("must lie in [lo, hi], got ...").
  int integer_in(long long lo, long long hi) const;
  std::string string() const;
  bool boolean() const;
  /// An array of 3 finite numbers.
  Eigen::Vector3d vec3() const;
  /// A non-zero 3-vector, normalised ("must be a non-zero vector").
  Eigen::Vector3d unit() const;

  /// Warns about each member not in `known`: ignored, not refused, so that a file written for a
  /// later version (or annotated with extra keys) still loads while a typo such as "gravty" does
  /// not pass unnoticed. Free-text keys are never warned about: comment, description, name,
  /// title and any key starting with '_' (docs/scene-format.md, docs/actions.md).
  void warn_unknown_keys(std::initializer_list<const char*> known) const;

 private:
  const nlohmann::json* value_;
  const JsonSource* source_;
  std::string path_;
};

}  // namespace bemsurg::io
