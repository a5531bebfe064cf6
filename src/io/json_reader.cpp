// The checked JSON reader (json_reader.hpp): the only file of bemsurg that walks a nlohmann::json
// tree it has read.
#include "json_reader.hpp"

#include <cmath>
#include <nlohmann/json.hpp>
#include <utility>

#include "bemsurg/error.hpp"

namespace bemsurg::io {

using nlohmann::json;

void fail_at(const std::string& key, const std::string& what) { throw SceneError(key.empty() ? what : key + ": " + what); }

std::string json_number_text(double x) { return json(x).dump(); }

JsonDocument::JsonDocument(const std::string& text, const std::string& name) {
  try {
    root_ = std::make_unique<json>(json::parse(text));
  } catch (const json::parse_error& e) {
    // nlohmann's message already holds the line and column of the problem.
    throw SceneError(name + ": not valid JSON: " + e.what());
  }
}

JsonDocument::~JsonDocument() = default;
JsonDocument::JsonDocument(JsonDocument&&) noexcept = default;

JsonReader::JsonReader(const json& value, const JsonSource& source, std::string path)
    : value_(&value), source_(&source), path_(std::move(path)) {}

std::string JsonReader::path_of(const std::string& key) const { return path_.empty() ? key : path_ + "." + key; }

std::string JsonReader::path_of(std::size_t index) const { return path_ + "[" + std::to_string(index) + "]"; }

void JsonReader::fail(const std::string& what) const { fail_at(path_, what); }

void JsonReader::fail_at(const std::string& path, const std::string& what) const {
  const std::string& name = source_->name;
  io::fail_at(name.empty() ? path : path.empty() ? name : name + ": " + path, what);
}

void JsonReader::warn(const std::string& what) const {
  if (source_->warnings == nullptr) return;
  const std::string& name = source_->name;
  source_->warnings->push_back((name.empty() ? "" : name + ": ") + path_ + ": " + what);
}

bool JsonReader::is_object() const { return value_->is_object(); }
bool JsonReader::is_array() const { return value_->is_array(); }
bool JsonReader::is_string() const { return value_->is_string(); }

std::size_t JsonReader::size() const { return value_->is_object() || value_->is_array() ? value_->size() : 0; }

std::string JsonReader::type_name() const {
  switch (value_->type()) {
    case json::value_t::null: return "null";
    case json::value_t::object: return "an object";
    case json::value_t::array: return "an array";
    case json::value_t::string: return "a string";
    case json::value_t::boolean: return "a boolean";
    default: return "a number";
  }
}

std::string JsonReader::dump() const { return value_->dump(); }

const JsonReader& JsonReader::object() const {
  if (!value_->is_object()) fail("expected an object, got " + type_name());
  return *this;
}

bool JsonReader::has(const std::string& key) const { return value_->is_object() && value_->contains(key); }

JsonReader JsonReader::required(const std::string& key) const {
  if (std::optional<JsonReader> member = optional(key)) return *member;
  fail_at(path_of(key), "missing (required)");
}

std::optional<JsonReader> JsonReader::optional(const std::string& key) const {
  const auto it = value_->find(key);  // end() for anything but an object
  if (it == value_->end()) return std::nullopt;
  return JsonReader(*it, *source_, path_of(key));
}

JsonReader JsonReader::operator[](std::size_t index) const { return JsonReader((*value_)[index], *source_, path_of(index)); }

std::vector<std::string> JsonReader::keys() const {
  std::vector<std::string> out;
  if (value_->is_object())
    for (auto it = value_->begin(); it != value_->end(); ++it) out.push_back(it.key());
  return out;
}

double JsonReader::number() const {
  if (!value_->is_number()) fail("expected a number, got " + type_name());
  const double x = value_->get<double>();
  if (!std::isfinite(x)) fail("expected a finite number");
  return x;
}

double JsonReader::positive() const {
  const double x = number();
  if (!(x > 0.0)) fail("must be positive, got " + json_number_text(x));
  return x;
}

double JsonReader::non_negative() const {
  const double x = number();
  if (x < 0.0) fail("must not be negative, got " + json_number_text(x));
  return x;
}

long long JsonReader::integer() const {
  if (value_->is_number_integer()) return value_->get<long long>();
  if (value_->is_number_float()) {
    const double x = value_->get<double>();
    if (std::isfinite(x) && x == std::floor(x) && std::abs(x) < 9.0e15) return static_cast<long long>(x);
    fail("expected an integer, got " + value_->dump());
  }
  fail("expected an integer, got " + type_name());
}

int JsonReader::integer_in(long long lo, long long hi) const {
  const long long x = integer();
  if (x < lo || x > hi) fail("must lie in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got " + std::to_string(x));
  return static_cast<int>(x);
}

std::string JsonReader::string() const {
  if (!value_->is_string()) fail("expected a string, got " + type_name());
  return value_->get<std::string>();
}

bool JsonReader::boolean() const {
  if (!value_->is_boolean()) fail("expected true or false, got " + type_name());
  return value_->get<bool>();
}

Eigen::Vector3d JsonReader::vec3() const {
  if (!value_->is_array() || value_->size() != 3)
    fail("expected an array of 3 numbers, got " + (value_->is_array() ? "an array of " + std::to_string(value_->size()) : type_name()));
  Eigen::Vector3d out;
  for (std::size_t i = 0; i < 3; ++i) out(static_cast<Eigen::Index>(i)) = (*this)[i].number();
  return out;
}

Eigen::Vector3d JsonReader::unit() const {
  const Eigen::Vector3d d = vec3();
  const double n = d.stableNorm();
  if (!(n > 0.0) || !std::isfinite(n)) fail("must be a non-zero vector");
  return d / n;
}

void JsonReader::warn_unknown_keys(std::initializer_list<const char*> known) const {
  if (!value_->is_object()) return;
  for (auto it = value_->begin(); it != value_->end(); ++it) {
    const std::string& k = it.key();
    if (k.empty() || k[0] == '_' || k == "comment" || k == "description" || k == "name" || k == "title") continue;
    bool found = false;
    for (const char* name : known) found = found || k == name;
    if (found) continue;
    std::string list;
    for (const char* name : known) list += (list.empty() ? "" : ", ") + std::string(name);
    JsonReader(it.value(), *source_, path_of(k)).warn("unknown key, ignored (known here: " + list + ")");
  }
}

}  // namespace bemsurg::io
