#pragma once
/// The one exception type clothbake throws for bad input. It carries the file
/// (when known), the offending field (a path such as "warp.width_mm" or
/// "objects[0].cloth") and what is wrong, so the message a user sees names all
/// three: "testscenes/x/cloth.json: warp.width_mm: must be greater than 0".

#include <stdexcept>
#include <string>

namespace clothbake {

class InputError : public std::runtime_error {
 public:
  InputError(std::string field, std::string message, std::string file = {})
      : std::runtime_error(compose(file, field, message)),
        m_file(std::move(file)),
        m_field(std::move(field)),
        m_message(std::move(message)) {}

  const std::string& file() const { return m_file; }
  const std::string& field() const { return m_field; }
  const std::string& message() const { return m_message; }

  /// The same error, attributed to `file` (kept if already set).
  InputError in_file(const std::string& file) const {
    return InputError(m_field, m_message, m_file.empty() ? file : m_file);
  }

 private:
  static std::string compose(const std::string& file, const std::string& field,
                             const std::string& message) {
    std::string s;
    if (!file.empty()) s += file + ": ";
    if (!field.empty()) s += field + ": ";
    return s + message;
  }
  std::string m_file, m_field, m_message;
};

}  // namespace clothbake
