#include "core/io/gltf_accessors.h"

#include <algorithm>
#include <cstring>

#include "core/error.h"

namespace penumbra {
namespace {

int componentBytes(int type) {
    switch (type) {
        case TINYGLTF_COMPONENT_TYPE_BYTE:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return 1;
        case TINYGLTF_COMPONENT_TYPE_SHORT:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return 2;
        case TINYGLTF_COMPONENT_TYPE_INT:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
        case TINYGLTF_COMPONENT_TYPE_FLOAT: return 4;
        default: return 0;
    }
}

int componentsOf(int type) {
    switch (type) {
        case TINYGLTF_TYPE_SCALAR: return 1;
        case TINYGLTF_TYPE_VEC2: return 2;
        case TINYGLTF_TYPE_VEC3: return 3;
        case TINYGLTF_TYPE_VEC4: return 4;
        default: return 0;  // matrices: not a vertex attribute Penumbra reads
    }
}

/// One component at p as glTF stores it, normalised if asked.
double value(const unsigned char* p, int type, bool normalized) {
    switch (type) {
        case TINYGLTF_COMPONENT_TYPE_BYTE: {
            const double v = static_cast<int8_t>(*p);
            return normalized ? std::max(v / 127.0, -1.0) : v;
        }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return normalized ? *p / 255.0 : *p;
        case TINYGLTF_COMPONENT_TYPE_SHORT: {
            int16_t v;
            std::memcpy(&v, p, 2);
            return normalized ? std::max(v / 32767.0, -1.0) : v;
        }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
            uint16_t v;
            std::memcpy(&v, p, 2);
            return normalized ? v / 65535.0 : v;
        }
        case TINYGLTF_COMPONENT_TYPE_INT: {
            int32_t v;
            std::memcpy(&v, p, 4);
            return v;
        }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
            uint32_t v;
            std::memcpy(&v, p, 4);
            return v;
        }
        default: {
            float v;
            std::memcpy(&v, p, 4);
            return v;
        }
    }
}

}  // namespace

GltfAccessors::GltfAccessors(const GltfFile& file) : file_(file) {
    for (const tinygltf::Buffer& b : file.model.buffers) bufferBytes_ += b.data.size();
}

void GltfAccessors::fail(const std::string& why) const {
    throw Error(ErrorCode::ParseError, file_.path.string() + ": cannot read as glTF: " + why);
}

const tinygltf::Accessor& GltfAccessors::accessor(int index, const std::string& what) const {
    const auto& all = file_.model.accessors;
    if (index < 0 || size_t(index) >= all.size()) fail(what + " names accessor " + std::to_string(index) + ", which does not exist");
    const tinygltf::Accessor& a = all[size_t(index)];
    const std::string where = "accessors[" + std::to_string(index) + "]";
    if (!componentsOf(a.type)) fail(where + ".type is not SCALAR or VEC2..4 (" + what + ")");
    if (!componentBytes(a.componentType)) fail(where + ".componentType is not a glTF component type");
    // Without a view the elements are zeros (and sparse values): as many as the file's buffers could describe.
    if (a.bufferView < 0 && a.count > std::max<uint64_t>(bufferBytes_, 1u << 16))
        fail(where + " has no bufferView and claims " + std::to_string(a.count) +
             " elements, more than the file's buffers could describe");
    return a;
}

size_t GltfAccessors::count(int index, const std::string& what) const { return accessor(index, what).count; }

int GltfAccessors::components(int index, const std::string& what) const { return componentsOf(accessor(index, what).type); }

const unsigned char* GltfAccessors::viewBytes(int viewIndex, uint64_t offset, uint64_t need, const std::string& by) const {
    const auto& views = file_.model.bufferViews;
    if (viewIndex < 0 || size_t(viewIndex) >= views.size())
        fail(by + " names bufferView " + std::to_string(viewIndex) + ", which does not exist");
    const tinygltf::BufferView& view = views[size_t(viewIndex)];
    const std::string where = "bufferViews[" + std::to_string(viewIndex) + "]";
    if (view.buffer < 0 || size_t(view.buffer) >= file_.model.buffers.size())
        fail(where + ".buffer names no entry of 'buffers'");
    const uint64_t have = file_.model.buffers[size_t(view.buffer)].data.size();
    if (view.byteOffset > have || view.byteLength > have - view.byteOffset)
        fail(where + " (byteOffset " + std::to_string(view.byteOffset) + ", byteLength " + std::to_string(view.byteLength) +
             ") reaches past its buffer's " + std::to_string(have) + " bytes");
    if (offset > view.byteLength || need > view.byteLength - offset)
        fail(by + " reads bytes up to " + std::to_string(offset + need) + " of " + where + ", which has " +
             std::to_string(view.byteLength));
    return file_.model.buffers[size_t(view.buffer)].data.data() + view.byteOffset + offset;
}

template <class T>
void GltfAccessors::read(const tinygltf::Accessor& a, int n, std::vector<T>& out, const std::string& where) const {
    const int size = componentBytes(a.componentType), element = size * n;
    out.assign(a.count * size_t(n), T(0));
    if (a.bufferView >= 0 && a.count > 0) {
        const tinygltf::BufferView& view = file_.model.bufferViews.at(size_t(a.bufferView));
        const uint64_t stride = view.byteStride ? view.byteStride : uint64_t(element);
        if (stride < uint64_t(element)) fail(where + ": its view's byteStride " + std::to_string(stride) + " is less than an element");
        // (count - 1) * stride cannot overflow: count is below 2^53 and the product is checked against the view.
        if (a.count - 1 > (uint64_t(1) << 40) / stride) fail(where + " claims " + std::to_string(a.count) + " elements");
        const unsigned char* p = viewBytes(a.bufferView, a.byteOffset, (a.count - 1) * stride + element, where);
        for (size_t i = 0; i < a.count; ++i)
            for (int c = 0; c < n; ++c) out[i * n + c] = T(value(p + i * stride + c * size, a.componentType, a.normalized));
    }
    if (!a.sparse.isSparse) return;
    const auto& sp = a.sparse;
    if (sp.count < 0 || uint64_t(sp.count) > a.count) fail(where + ".sparse.count is more than the accessor's count");
    const int indexSize = componentBytes(sp.indices.componentType);
    if (indexSize == 0 || sp.indices.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT || sp.indices.byteOffset < 0 ||
        sp.values.byteOffset < 0)
        fail(where + ".sparse.indices or values are malformed");
    const unsigned char* idx = viewBytes(sp.indices.bufferView, uint64_t(sp.indices.byteOffset),
                                         uint64_t(sp.count) * indexSize, where + ".sparse.indices");
    const unsigned char* val =
        viewBytes(sp.values.bufferView, uint64_t(sp.values.byteOffset), uint64_t(sp.count) * element, where + ".sparse.values");
    for (int k = 0; k < sp.count; ++k) {
        const double target = value(idx + size_t(k) * indexSize, sp.indices.componentType, false);
        if (!(target >= 0.0) || target >= double(a.count)) fail(where + ".sparse.indices holds an index past the accessor's count");
        for (int c = 0; c < n; ++c)
            out[size_t(target) * n + c] = T(value(val + size_t(k) * element + c * size, a.componentType, a.normalized));
    }
}

std::vector<float> GltfAccessors::floats(int index, int n, const std::string& what) const {
    const tinygltf::Accessor& a = accessor(index, what);
    const std::string where = "accessors[" + std::to_string(index) + "]";
    if (componentsOf(a.type) != n)
        fail(what + " must be a " + (n == 1 ? std::string("SCALAR") : "VEC" + std::to_string(n)) + " accessor (" + where + ")");
    std::vector<float> out;
    read(a, n, out, where);
    return out;
}

std::vector<uint32_t> GltfAccessors::indices(int index, const std::string& what) const {
    const tinygltf::Accessor& a = accessor(index, what);
    const std::string where = "accessors[" + std::to_string(index) + "]";
    const int t = a.componentType;
    if (a.type != TINYGLTF_TYPE_SCALAR || !(t == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
                                            t == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT || t == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT))
        fail(what + " must be a SCALAR accessor of unsigned integers (" + where + ")");
    std::vector<uint32_t> out;
    read(a, 1, out, where);
    return out;
}

}  // namespace penumbra
