// A SAX handler that builds the document itself: nlohmann's callback parser
// rescans an object's members after each child (quadratic in 100k materials),
// and ordered_json's insertion searches the keys (quadratic again).
#include "core/io/json_document.h"

#include <algorithm>
#include <cctype>
#include <memory>
#include <unordered_set>
#include <utility>
#include <vector>

#include "core/error.h"
#include "core/io/json_text.h"

namespace penumbra {
namespace {

using namespace json_text;

/// 1-based line and column of a 0-based byte offset (clamped to the end of the text).
std::pair<size_t, size_t> lineColumn(const std::string& text, size_t offset) {
    offset = std::min(offset, text.size());
    size_t line = 1 + static_cast<size_t>(std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(offset), '\n'));
    size_t lineStart = text.rfind('\n', offset == 0 ? std::string::npos : offset - 1);
    lineStart = (offset == 0 || lineStart == std::string::npos) ? 0 : lineStart + 1;
    return {line, offset - lineStart + 1};
}

/// Caps text quoted from the file (nlohmann quotes whole tokens: a 10 MB string
/// or number would make a 10 MB message) and keeps the message on one line.
std::string shortened(std::string s) {
    constexpr size_t kMax = 200;
    if (s.size() > kMax) s = s.substr(0, kMax) + "...";
    for (char& c : s)
        if (c == '\n' || c == '\r') c = ' ';
    return s;
}

/// nlohmann's message without its "[json.exception...] parse error at line L, column C: "
/// prefix (its line/column count the character after the error, so we compute our own).
std::string parseErrorDetail(const std::string& what) {
    std::string s = what;
    if (auto close = s.find("] "); s.rfind("[json.exception", 0) == 0 && close != std::string::npos) s = s.substr(close + 2);
    if (s.rfind("parse error", 0) == 0) {
        if (auto colon = s.find(": "); colon != std::string::npos) s = s.substr(colon + 2);
    }
    if (s.rfind("syntax error ", 0) == 0) s = s.substr(13);
    return shortened(s);
}

class DocumentBuilder {
public:
    DocumentBuilder(const std::string& text, const std::string& file) : text_(text), file_(file) {}

    Json take() { return std::move(root_); }

    bool null() { return put(Json(nullptr)); }
    bool boolean(bool v) { return put(Json(v)); }
    bool number_integer(Json::number_integer_t v) { return put(Json(v)); }
    bool number_unsigned(Json::number_unsigned_t v) { return put(Json(v)); }
    bool number_float(Json::number_float_t v, const Json::string_t&) { return put(Json(v)); }
    bool string(Json::string_t& v) { return put(Json(std::move(v))); }
    bool binary(Json::binary_t&) { return put(Json(nullptr)); }  // not produced by text JSON

    bool start_object(std::size_t) {
        open(Json(Json::value_t::object), false);
        return true;
    }
    bool start_array(std::size_t) {
        open(Json(Json::value_t::array), true);
        return true;
    }
    bool end_object() { return close(); }
    bool end_array() { return close(); }

    bool key(Json::string_t& k) {
        Frame& top = stack_.back();
        auto& members = *top.value->get_ptr<Json::object_t*>();
        if (isDuplicate(top, members, k))
            throw Error(ErrorCode::ParseError, oneLine(file_ + ": " + shortPointer(pointer(&k)) + ": duplicate key"));
        members.emplace_back(std::move(k), Json());
        return true;
    }

    bool parse_error(std::size_t position, const std::string& lastToken, const nlohmann::detail::exception& ex) {
        if (ex.id == 406) {
            // Number overflow ("1e999"): the position is the end of the literal.
            size_t start = position >= lastToken.size() ? position - lastToken.size() : 0;
            auto [line, col] = lineColumn(text_, start);
            throw Error(ErrorCode::ParseError, file_ + ":" + std::to_string(line) + ":" + std::to_string(col) +
                                                   ": JSON number out of range: " + parseErrorDetail(ex.what()));
        }
        // The position counts the characters read, the offending one included.
        size_t offset = position > 0 ? position - 1 : 0;
        if (const auto* pe = dynamic_cast<const nlohmann::detail::parse_error*>(&ex))
            offset = pe->byte > 0 ? static_cast<size_t>(pe->byte) - 1 : 0;
        auto [line, col] = lineColumn(text_, offset);
        throw Error(ErrorCode::ParseError, file_ + ":" + std::to_string(line) + ":" + std::to_string(col) +
                                               ": JSON syntax error: " + parseErrorDetail(ex.what()));
    }

private:
    // Objects up to this size are searched for a duplicate key; larger ones keep a hash set.
    static constexpr size_t kLinearKeys = 16;

    struct Frame {
        Json* value;
        bool isArray;
        std::unique_ptr<std::unordered_set<std::string>> keys;  // large objects only
    };

    /// Where the next value goes: the root, the end of an array, or the member whose key was just read.
    Json* slot() {
        if (stack_.empty()) return &root_;
        Frame& top = stack_.back();
        if (top.isArray) {
            auto& items = *top.value->get_ptr<Json::array_t*>();
            items.emplace_back();
            return &items.back();
        }
        return &top.value->get_ptr<Json::object_t*>()->back().second;
    }
    bool put(Json&& v) {
        *slot() = std::move(v);
        return true;
    }
    void open(Json&& v, bool isArray) {
        Json* s = slot();
        *s = std::move(v);
        stack_.push_back(Frame{s, isArray, nullptr});
    }
    bool close() {
        stack_.pop_back();
        return true;
    }

    static bool isDuplicate(Frame& top, const Json::object_t& members, const std::string& k) {
        if (!top.keys) {
            for (const auto& m : members)
                if (m.first == k) return true;
            if (members.size() < kLinearKeys) return false;
            top.keys = std::make_unique<std::unordered_set<std::string>>();
            for (const auto& m : members) top.keys->insert(m.first);
        }
        return !top.keys->insert(k).second;
    }

    /// The pointer of the value being read, ending in `key` when given.
    std::string pointer(const std::string* key) const {
        std::string p;
        for (size_t i = 0; i < stack_.size(); ++i) {
            const Frame& f = stack_[i];
            const bool last = i + 1 == stack_.size();
            p += '/';  // appended, not rebuilt: 50,000 levels stay linear
            if (f.isArray)
                p += std::to_string(f.value->size() - 1);
            else
                p += pointerToken(last && key ? *key : f.value->get_ptr<const Json::object_t*>()->back().first);
        }
        return p;
    }

    const std::string& text_;
    const std::string& file_;
    Json root_;
    std::vector<Frame> stack_;
};

}  // namespace

Json parseJsonDocument(const std::string& text, const std::string& file) {
    DocumentBuilder builder(text, file);
    Json::sax_parse(text, &builder, nlohmann::detail::input_format_t::json, /*strict=*/true, /*ignore_comments=*/true);
    return builder.take();
}

}  // namespace penumbra
