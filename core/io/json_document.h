// Parsing a JSON scene file into a document: one pass over the text, linear in
// its length (objects are filled without nlohmann's per-key search, duplicate
// keys are found with a hash set per large object), with errors that give the
// file, line and column, or the JSON pointer of a duplicate key.
#pragma once

#include <nlohmann/json.hpp>

#include <string>

namespace penumbra {

/// Objects keep their keys in file order, so materials and errors come in file order.
using Json = nlohmann::ordered_json;

/// Parses `text` (comments allowed); throws Error(ParseError) naming `file`
/// with line and column, or with the (bounded) JSON pointer of a duplicate key.
Json parseJsonDocument(const std::string& text, const std::string& file);

}  // namespace penumbra
