#include "core/io/xml_checks.h"

#include <pugixml.hpp>

#include <algorithm>
#include <cstdint>
#include <functional>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "core/io/nesting_checks.h"

namespace penumbra {
namespace {

using Node = pugi::xml_node;

struct Invalid {
    std::string why;
};

std::string lineOf(const std::string& bytes, const Node& n) {
    const size_t at = std::min(bytes.size(), size_t(std::max<ptrdiff_t>(n.offset_debug(), 0)));
    return "line " + std::to_string(1 + std::count(bytes.begin(), bytes.begin() + std::ptrdiff_t(at), '\n'));
}

/// "<name> on line N", for messages.
std::string named(const std::string& bytes, const Node& n) {
    return "<" + std::string(n.name()).substr(0, 40) + "> on " + lineOf(bytes, n);
}

/// Calls visit(element, depth) for every element below `root` in document
/// order, depth 1 for root's children; a loop over pugixml's links.
void forEachElement(const Node& root, const std::function<void(const Node&, size_t)>& visit) {
    size_t depth = 1;
    for (Node n = root.first_child(); n && n != root;) {
        if (n.type() == pugi::node_element) visit(n, depth);
        if (n.first_child()) {
            n = n.first_child();
            ++depth;
            continue;
        }
        while (n != root && !n.next_sibling()) {
            n = n.parent();
            --depth;
        }
        if (n != root) n = n.next_sibling();
    }
}

/// The descendants of `n` named `name`, in document order.
std::vector<Node> descendants(const Node& n, const char* name) {
    std::vector<Node> out;
    forEachElement(n, [&](const Node& e, size_t) {
        if (std::string_view(e.name()) == name) out.push_back(e);
    });
    return out;
}

/// "#id" -> "id"; empty for any other reference (Assimp refuses those itself).
std::string localRef(const Node& n, const char* attribute) {
    const std::string v = n.attribute(attribute).as_string();
    return v.size() > 1 && v[0] == '#' ? v.substr(1) : std::string();
}

/// Whitespace-separated tokens of an element's text; with `integers`, throws
/// unless each is [+-]digits, which is all Assimp's index reader can step over
/// (it reads "1x" for ever).
size_t tokens(const std::string& bytes, const Node& n, bool integers) {
    const std::string_view t = n.text().get();
    size_t count = 0;
    for (size_t i = 0; i < t.size();) {
        if (t[i] == ' ' || t[i] == '\t' || t[i] == '\r' || t[i] == '\n') {
            ++i;
            continue;
        }
        const size_t from = i;
        while (i < t.size() && !(t[i] == ' ' || t[i] == '\t' || t[i] == '\r' || t[i] == '\n')) ++i;
        const std::string_view token = t.substr(from, i - from);
        const size_t sign = token[0] == '+' || token[0] == '-';
        if (integers && (token.size() == sign || token.find_first_not_of("0123456789", sign) != std::string_view::npos))
            throw Invalid{named(bytes, n) + " holds '" + std::string(token.substr(0, 20)) + "' where an integer was expected"};
        ++count;
    }
    return count;
}

/// Every <node> reached through child nodes and <instance_node> references:
/// no cycle, and the expanded tree no deeper than kMaxModelNesting and no
/// larger than kMaxModelNodes. Assimp resolves a reference by id or else by
/// name to one node; each distinct reference here is a vertex of its own that
/// stands for every node it may resolve to (the worst of them counts), so the
/// graph stays as small as the file.
void checkNodeGraph(const std::string& bytes, const Node& root) {
    const std::vector<Node> nodes = descendants(root, "node");
    const size_t n = nodes.size();
    std::unordered_map<pugi::xml_node_struct*, size_t> indexOf;  // pugixml's handle -> vertex
    for (size_t i = 0; i < n; ++i) indexOf[nodes[i].internal_object()] = i;
    std::unordered_map<std::string, size_t> refOf;  // reference -> vertex (n and above)
    std::vector<std::vector<size_t>> edges(n);
    for (size_t i = 0; i < n; ++i)
        for (const Node& c : nodes[i].children()) {
            if (std::string_view(c.name()) == "node") edges[i].push_back(indexOf.at(c.internal_object()));
            if (std::string_view(c.name()) != "instance_node") continue;
            const auto [it, fresh] = refOf.try_emplace(localRef(c, "url"), edges.size());
            if (fresh) edges.emplace_back();
            edges[i].push_back(it->second);
        }
    for (size_t i = 0; i < n; ++i)
        for (const char* key : {"id", "name"})
            if (auto it = refOf.find(nodes[i].attribute(key).as_string()); it != refOf.end() && !it->first.empty())
                edges[it->second].push_back(i);

    enum : uint8_t { kNew, kOpen, kDone };
    std::vector<uint8_t> state(edges.size(), kNew);
    std::vector<uint64_t> depth(edges.size(), 0), size(edges.size(), 0);
    for (size_t start = 0; start < n; ++start) {
        if (state[start] != kNew) continue;
        std::vector<std::pair<size_t, size_t>> stack{{start, 0}};  // vertex, next edge
        state[start] = kOpen;
        while (!stack.empty()) {
            auto& [v, next] = stack.back();
            const size_t node = v < n ? v : stack[stack.size() - 2].first;  // a reference's parent is a node
            if (next < edges[v].size()) {
                const size_t c = edges[v][next++];
                if (state[c] == kOpen) throw Invalid{named(bytes, nodes[node]) + " contains or instances itself or an ancestor"};
                if (state[c] == kNew) {
                    state[c] = kOpen;
                    stack.emplace_back(c, 0);
                }
                continue;
            }
            for (size_t c : edges[v]) {
                depth[v] = std::max(depth[v], depth[c]);
                size[v] = v < n ? std::min<uint64_t>(size[v] + size[c], kMaxModelNodes + 1) : std::max(size[v], size[c]);
            }
            if (v < n) {
                depth[v] += 1;
                size[v] = std::min<uint64_t>(size[v] + 1, kMaxModelNodes + 1);
                if (depth[v] > kMaxModelNesting)
                    throw Invalid{nestingProblem("COLLADA nodes (with their <instance_node> references)", lineOf(bytes, nodes[v]))};
                if (size[v] > kMaxModelNodes)
                    throw Invalid{named(bytes, nodes[v]) + " expands to more than " + std::to_string(kMaxModelNodes) +
                                  " nodes through its <instance_node> references"};
            }
            state[v] = kDone;
            stack.pop_back();
        }
    }
}

/// A controller's skin or morph names the mesh or controller it deforms;
/// Assimp follows such names until one is no controller, for ever in a loop.
void checkControllers(const std::string& bytes, const Node& root) {
    std::unordered_map<std::string, std::string> target;  // controller id -> what it deforms
    std::unordered_map<std::string, Node> byId;
    for (const Node& c : descendants(root, "controller")) {
        const std::string id = c.attribute("id").as_string();
        for (const Node& part : c.children()) {
            const std::string_view name = part.name();
            const std::string source = part.attribute("source").as_string();
            if ((name == "skin" || name == "morph") && !source.empty()) target[id] = source.substr(1);
        }
        byId[id] = c;
    }
    for (const auto& [id, first] : target) {
        std::string at = first;
        for (size_t steps = 0; target.count(at); ++steps) {
            if (steps > target.size())
                throw Invalid{named(bytes, byId[id]) + " deforms a chain of controllers that loops"};
            at = target[at];
        }
    }
}

/// Data arrays hold the values their count claims, and every accessor that a
/// mesh input reads stays inside its array: Assimp reads values at offset +
/// index * stride + (a parameter's place) without a bound, and an array of
/// strings, or one whose count is not a number, holds no values at all.
void checkAccessors(const std::string& bytes, const Node& root) {
    std::unordered_map<std::string, uint64_t> values;  // array id -> values as Assimp reads them
    std::unordered_map<std::string, Node> sources;
    forEachElement(root, [&](const Node& e, size_t) {
        const std::string_view name = e.name();
        if (name == "source") sources[e.attribute("id").as_string()] = e;
        if (name != "float_array" && name != "IDREF_array" && name != "Name_array") return;
        const uint64_t count = e.attribute("count").as_uint();
        const size_t held = tokens(bytes, e, false);
        if (count > held)
            throw Invalid{named(bytes, e) + " declares " + std::to_string(count) + " values but holds " + std::to_string(held)};
        values[e.attribute("id").as_string()] = name == "float_array" ? count : 0;
    });
    std::unordered_set<std::string> checked;  // sources whose accessors were checked
    for (const char* parent : {"vertices", "triangles", "lines", "linestrips", "polygons", "polylist", "trifans", "tristrips"})
        for (const Node& p : descendants(root, parent))
            for (const Node& input : descendants(p, "input")) {
                if (std::string_view(input.attribute("semantic").as_string()) == "VERTEX") continue;
                const auto source = sources.find(localRef(input, "source"));
                if (source == sources.end() || !checked.insert(source->first).second) continue;  // unknown: Assimp refuses it
                for (const Node& a : descendants(source->second, "accessor")) {
                    const auto array = values.find(localRef(a, "source"));
                    if (array == values.end()) continue;
                    const int64_t count = a.attribute("count").as_int();
                    const uint64_t stride = a.attribute("stride").as_uint(1), offset = a.attribute("offset").as_uint();
                    const uint64_t params = std::max<uint64_t>(descendants(a, "param").size(), 1);
                    if (count < 0) throw Invalid{named(bytes, a) + " has a negative count"};
                    if (count > 0 && offset + uint64_t(count - 1) * stride + params > array->second)
                        throw Invalid{named(bytes, a) + " reads " + std::to_string(offset + uint64_t(count - 1) * stride + params) +
                                      " values of an array that holds " + std::to_string(array->second)};
                }
            }
}

/// Primitives: a VERTEX input (Assimp indexes with its offset, unset without
/// one), integer indices and counts, and no more primitives than indices.
void checkPrimitives(const std::string& bytes, const Node& root) {
    for (const char* kind : {"triangles", "lines", "linestrips", "polygons", "polylist", "trifans", "tristrips"})
        for (const Node& prim : descendants(root, kind)) {
            size_t indices = 0;
            for (const Node& p : descendants(prim, "p")) indices += tokens(bytes, p, true);
            for (const Node& v : descendants(prim, "vcount")) tokens(bytes, v, true);
            const uint64_t count = prim.attribute("count").as_uint();
            if (count > indices)
                throw Invalid{named(bytes, prim) + " declares " + std::to_string(count) + " primitives but holds " +
                              std::to_string(indices) + " indices"};
            const std::vector<Node> inputs = descendants(prim, "input");
            if (indices > 0 && std::none_of(inputs.begin(), inputs.end(), [](const Node& i) {
                    return std::string_view(i.attribute("semantic").as_string()) == "VERTEX";
                }))
                throw Invalid{named(bytes, prim) + " has no VERTEX input"};
        }
}

}  // namespace

std::optional<std::string> xmlModelProblem(const std::string& bytes, bool collada) {
    pugi::xml_document doc;
    const pugi::xml_parse_result parsed = doc.load_buffer(bytes.data(), bytes.size(), pugi::parse_full);
    if (!parsed)
        return std::string("not well-formed XML (") + parsed.description() + " at byte " + std::to_string(parsed.offset) + ")";
    try {
        forEachElement(doc, [&](const Node& e, size_t depth) {
            if (depth > kMaxModelNesting) throw Invalid{nestingProblem("XML elements", lineOf(bytes, e))};
        });
        if (collada) {
            checkNodeGraph(bytes, doc);
            checkControllers(bytes, doc);
            checkAccessors(bytes, doc);
            checkPrimitives(bytes, doc);
        }
    } catch (const Invalid& e) {
        return e.why;
    }
    return std::nullopt;
}

}  // namespace penumbra
