#pragma once
/// Typed, path-aware access to a JSON document, so every error names the file
/// and the field ("objects[2].cloth.warp.width_mm") and unknown keys (typos)
/// are refused instead of silently ignored.

#include <cstdint>
#include <initializer_list>
#include <string>
#include <vector>

#include <Imath/ImathVec.h>
#include <nlohmann/json.hpp>

namespace clothbake::io {

/// "a number", "a string", ... for messages about wrong types.
std::string json_type_name(const nlohmann::json& value);

/// Parses JSON text read from `path` (named in errors only). Errors name the
/// file and, for syntax errors, the line and column. Throws InputError.
nlohmann::json parse_json_text(const std::string& text, const std::string& path);

/// read_text_file, then parse_json_text.
nlohmann::json read_json_file(const std::string& path);

class JsonObject {
 public:
  /// `value` must outlive this object. Throws unless it is a JSON object.
  JsonObject(const nlohmann::json& value, std::string path, std::string file);

  bool has(const char* key) const { return m_value.contains(key); }
  /// Refuses keys that are not in `known` (call after reading, or before).
  void allow_only(std::initializer_list<const char*> known) const;

  /// Each reader leaves `out` unchanged when the key is absent (the default).
  void read(const char* key, float& out) const;
  void read(const char* key, double& out) const;  ///< kept whole: a value written as double reads back exact
  void read(const char* key, int& out) const;
  void read(const char* key, bool& out) const;
  void read(const char* key, uint64_t& out) const;
  void read(const char* key, std::string& out) const;
  void read(const char* key, Imath::V3f& out) const;                     ///< [x, y, z]
  void read(const char* key, Imath::V2f& out) const;                     ///< [x, y]
  void read(const char* key, std::vector<std::vector<int>>& out) const;  ///< matrix of ints
  void read(const char* key, std::vector<Imath::V3f>& out) const;        ///< [[x, y, z], ...]
  void read(const char* key, std::vector<float>& out) const;             ///< [x, ...]

  JsonObject object(const char* key) const;  ///< required nested object
  const nlohmann::json& raw(const char* key) const { return m_value.at(key); }
  std::string field(const char* key) const { return m_path.empty() ? key : m_path + "." + key; }
  const std::string& path() const { return m_path; }
  const std::string& file() const { return m_file; }

  [[noreturn]] void fail(const std::string& field_path, const std::string& message) const;

 private:
  const nlohmann::json& m_value;
  std::string m_path, m_file;
};

}  // namespace clothbake::io
