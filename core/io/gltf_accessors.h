// glTF accessors read into plain arrays, every byte checked first: the
// accessor inside its buffer view, the view inside its buffer, sparse
// indices and values inside theirs, and counts no larger than the file's
// buffers can describe (tinygltf checks none of this).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/io/gltf_model.h"

namespace penumbra {

class GltfAccessors {
public:
    explicit GltfAccessors(const GltfFile& file);

    /// The elements of accessor `index`, `components` floats each (its type
    /// must have that many: 2 for VEC2, ...): floats as they are, integers
    /// normalised to [0, 1] or [-1, 1] where the accessor says so, else as
    /// numbers (KHR_mesh_quantization). Error(ParseError) naming the file and
    /// the accessor when it does not fit; `what` names the use ("POSITION").
    std::vector<float> floats(int index, int components, const std::string& what) const;
    /// An index accessor: SCALAR unsigned bytes, shorts or ints.
    std::vector<uint32_t> indices(int index, const std::string& what) const;
    /// Accessor `index`'s element count and components per element (checked as floats() checks them).
    size_t count(int index, const std::string& what) const;
    int components(int index, const std::string& what) const;
    /// Error(ParseError): "<file>: cannot read as glTF: <why>".
    [[noreturn]] void fail(const std::string& why) const;

private:
    const tinygltf::Accessor& accessor(int index, const std::string& what) const;
    /// The bytes of view `view` from `offset`, `need` of them, checked; `by` names the reader.
    const unsigned char* viewBytes(int view, uint64_t offset, uint64_t need, const std::string& by) const;
    /// Reads the elements' component values (any component type) into out (count x n).
    template <class T>
    void read(const tinygltf::Accessor& a, int n, std::vector<T>& out, const std::string& where) const;

    const GltfFile& file_;
    uint64_t bufferBytes_ = 0;  // all buffers together: what bounds an accessor without a view
};

}  // namespace penumbra
