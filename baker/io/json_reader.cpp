#include "io/json_reader.h"

#include <cmath>
#include <limits>

#include "core/util/error.h"
#include "io/text_file.h"

namespace clothbake::io {

std::string json_type_name(const nlohmann::json& v) {
  if (v.is_number()) return "a number";
  if (v.is_string()) return "a string";
  if (v.is_boolean()) return "a boolean";
  if (v.is_null()) return "null";
  if (v.is_array()) return "an array";
  return "an object";
}

namespace {
std::string type_name(const nlohmann::json& v) { return json_type_name(v); }

// Line and column of a byte offset, for syntax errors a person can find.
std::string line_col(const std::string& text, size_t byte) {
  size_t line = 1, col = 1;
  for (size_t i = 0; i < byte && i < text.size(); ++i) {
    if (text[i] == '\n') {
      ++line;
      col = 1;
    } else {
      ++col;
    }
  }
  return "line " + std::to_string(line) + ", column " + std::to_string(col);
}
}  // namespace

nlohmann::json read_json_file(const std::string& path) {
  return parse_json_text(read_text_file(path, "a JSON file"), path);
}

nlohmann::json parse_json_text(const std::string& text, const std::string& path) {
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    std::string what = e.what();
    // nlohmann's message starts with "[json.exception.parse_error.101] parse error at ...".
    const auto colon = what.find("parse error");
    if (colon != std::string::npos) what = what.substr(colon);
    throw InputError(
        "", "malformed JSON at " + line_col(text, e.byte ? e.byte - 1 : 0) + " (" + what + ")",
        path);
  } catch (const nlohmann::json::exception& e) {
    // e.g. out_of_range 406 for 1e999: JSON numbers must fit a double.
    std::string what = e.what();
    const auto bracket = what.find("] ");
    if (bracket != std::string::npos) what = what.substr(bracket + 2);
    throw InputError("", "invalid JSON: " + what + " (numbers must be finite)", path);
  }
}

JsonObject::JsonObject(const nlohmann::json& value, std::string path, std::string file)
    : m_value(value), m_path(std::move(path)), m_file(std::move(file)) {
  if (!m_value.is_object()) fail(m_path, "expected an object, got " + type_name(m_value));
}

void JsonObject::fail(const std::string& field_path, const std::string& message) const {
  throw InputError(field_path, message, m_file);
}

void JsonObject::allow_only(std::initializer_list<const char*> known) const {
  for (const auto& [key, value] : m_value.items()) {
    bool ok = false;
    for (const char* k : known) ok = ok || key == k;
    if (!ok) {
      std::string list;
      for (const char* k : known) list += std::string(list.empty() ? "" : ", ") + k;
      fail(field(key.c_str()), "unknown key; expected one of: " + list);
    }
  }
}

void JsonObject::read(const char* key, float& out) const {
  if (!has(key)) return;
  const auto& v = m_value.at(key);
  if (!v.is_number()) fail(field(key), "expected a number, got " + type_name(v));
  const double d = v.get<double>();
  if (!std::isfinite(d) || std::fabs(d) > std::numeric_limits<float>::max())
    fail(field(key), "must be a finite number");
  out = static_cast<float>(d);
}

void JsonObject::read(const char* key, double& out) const {
  if (!has(key)) return;
  const auto& v = m_value.at(key);
  if (!v.is_number()) fail(field(key), "expected a number, got " + type_name(v));
  const double d = v.get<double>();
  if (!std::isfinite(d)) fail(field(key), "must be a finite number");
  out = d;
}

void JsonObject::read(const char* key, bool& out) const {
  if (!has(key)) return;
  const auto& v = m_value.at(key);
  if (!v.is_boolean()) fail(field(key), "expected true or false, got " + type_name(v));
  out = v.get<bool>();
}

void JsonObject::read(const char* key, int& out) const {
  if (!has(key)) return;
  const auto& v = m_value.at(key);
  if (!v.is_number_integer())
    fail(field(key),
         "expected an integer, got " + type_name(v) + (v.is_number() ? " with a fraction" : ""));
  // An unsigned value above INT64_MAX would wrap to a negative int64_t.
  if (v.is_number_unsigned() && v.get<uint64_t>() > uint64_t(std::numeric_limits<int>::max()))
    fail(field(key), "integer out of range: " + v.dump());
  const int64_t i = v.get<int64_t>();
  if (i < std::numeric_limits<int>::min() || i > std::numeric_limits<int>::max())
    fail(field(key), "integer out of range: " + std::to_string(i));
  out = static_cast<int>(i);
}

void JsonObject::read(const char* key, uint64_t& out) const {
  if (!has(key)) return;
  const auto& v = m_value.at(key);
  if (!v.is_number_integer() || (v.is_number_integer() && !v.is_number_unsigned()))
    fail(field(key), "expected a non-negative integer, got " + type_name(v));
  out = v.get<uint64_t>();
}

void JsonObject::read(const char* key, std::string& out) const {
  if (!has(key)) return;
  const auto& v = m_value.at(key);
  if (!v.is_string()) fail(field(key), "expected a string, got " + type_name(v));
  out = v.get<std::string>();
}

namespace {
// A fixed-length array of finite numbers that fit a float.
template <int N, typename Vec>
void read_vector(const JsonObject& j, const nlohmann::json& v, const std::string& field, Vec& out) {
  static const char* const k_count[] = {"", "one", "two", "three"};
  if (!v.is_array() || v.size() != N)
    j.fail(field, std::string("expected an array of ") + k_count[N] + " numbers, got " +
                      type_name(v) + (v.is_array() ? " of " + std::to_string(v.size()) : ""));
  for (int c = 0; c < N; ++c) {
    if (!v[c].is_number())
      j.fail(field + "[" + std::to_string(c) + "]", "expected a number, got " + type_name(v[c]));
    const double d = v[c].get<double>();
    if (!std::isfinite(d) || std::fabs(d) > std::numeric_limits<float>::max())
      j.fail(field + "[" + std::to_string(c) + "]", "must be a finite number");
    out[c] = static_cast<float>(d);
  }
}
}  // namespace

void JsonObject::read(const char* key, Imath::V3f& out) const {
  if (has(key)) read_vector<3>(*this, m_value.at(key), field(key), out);
}

void JsonObject::read(const char* key, Imath::V2f& out) const {
  if (has(key)) read_vector<2>(*this, m_value.at(key), field(key), out);
}

void JsonObject::read(const char* key, std::vector<std::vector<int>>& out) const {
  if (!has(key)) return;
  const auto& v = m_value.at(key);
  if (!v.is_array()) fail(field(key), "expected an array of rows, got " + type_name(v));
  std::vector<std::vector<int>> m;
  for (size_t r = 0; r < v.size(); ++r) {
    const std::string row_field = field(key) + "[" + std::to_string(r) + "]";
    if (!v[r].is_array()) fail(row_field, "expected an array of 0/1, got " + type_name(v[r]));
    std::vector<int> row;
    for (size_t c = 0; c < v[r].size(); ++c) {
      const auto& e = v[r][c];
      if (!e.is_number_integer())
        fail(row_field + "[" + std::to_string(c) + "]", "expected 0 or 1, got " + type_name(e));
      const int64_t x = e.get<int64_t>();
      row.push_back(x < -1000 || x > 1000 ? 1000 : static_cast<int>(x));
    }
    m.push_back(std::move(row));
  }
  out = std::move(m);
}

void JsonObject::read(const char* key, std::vector<Imath::V3f>& out) const {
  if (!has(key)) return;
  const auto& v = m_value.at(key);
  if (!v.is_array() || v.empty())
    fail(field(key), "expected a non-empty array of [r, g, b], got " + type_name(v));
  std::vector<Imath::V3f> list(v.size());
  for (size_t i = 0; i < v.size(); ++i)
    read_vector<3>(*this, v[i], field(key) + "[" + std::to_string(i) + "]", list[i]);
  out = std::move(list);
}

void JsonObject::read(const char* key, std::vector<float>& out) const {
  if (!has(key)) return;
  const auto& v = m_value.at(key);
  if (!v.is_array() || v.empty())
    fail(field(key), "expected a non-empty array of numbers, got " + type_name(v));
  std::vector<float> list(v.size());
  for (size_t i = 0; i < v.size(); ++i) {
    if (!v[i].is_number())
      fail(field(key) + "[" + std::to_string(i) + "]", "expected a number, got " + type_name(v[i]));
    const double x = v[i].get<double>();
    if (!std::isfinite(x) || std::fabs(x) > std::numeric_limits<float>::max())
      fail(field(key) + "[" + std::to_string(i) + "]", "must be a finite number");
    list[i] = float(x);
  }
  out = std::move(list);
}

JsonObject JsonObject::object(const char* key) const {
  if (!has(key)) fail(field(key), "missing");
  return JsonObject(m_value.at(key), field(key), m_file);
}

}  // namespace clothbake::io
