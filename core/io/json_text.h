// JSON pointers and quoted file text, made safe for one-line error messages.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace penumbra::json_text {

/// Keys and names quoted in messages are cut to this many bytes.
constexpr size_t kMaxQuoted = 64;
/// A JSON pointer in a message keeps its first and last parts within this many bytes.
constexpr size_t kMaxPointer = 240;

/// Escapes one reference token of a JSON pointer (RFC 6901: '~' -> "~0", '/' -> "~1"), cut to kMaxQuoted.
std::string pointerToken(std::string_view key);
inline std::string child(const std::string& ptr, std::string_view key) { return ptr + "/" + pointerToken(key); }
inline std::string child(const std::string& ptr, size_t index) { return ptr + "/" + std::to_string(index); }

/// A pointer of at most about kMaxPointer bytes: a 50,000-level path keeps its
/// head and tail with "/...(N levels)..." between them.
std::string shortPointer(const std::string& ptr);

/// A string from the file, in double quotes, cut to kMaxQuoted bytes.
std::string quotedValue(std::string_view s);

/// Control characters (a JSON string may hold "\n") would split the one-line message.
std::string oneLine(std::string s);

}  // namespace penumbra::json_text
