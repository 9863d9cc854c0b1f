// The OBJ pre-pass: what tinyobjloader is lenient about is settled here first
// (BOM, line endings, face indices, coordinate checks), keeping line numbers,
// so that every face can be validated and reported by line afterwards.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace penumbra {

/// One face corner, 0-based, -1 for no vt / vn (the layout tinyobjloader uses).
struct ObjCorner {
    int vertex_index;
    int normal_index;
    int texcoord_index;
};

// tinyobjloader stores the corner count of a face in an unsigned char; bigger
// faces bypass it (BigFace).
constexpr size_t kMaxFaceCorners = 255;

/// A face with more corners than tinyobjloader can count: it parses a triangle
/// in its place (keeping the shape, material and face order), and the loader
/// takes the corners from here.
struct BigFace {
    size_t face;                      // index among the faces tinyobjloader reports
    std::vector<ObjCorner> corners;  // 0-based, -1 for no vt / vn
};

struct PreparedObj {
    std::string text;                 // what tinyobjloader parses
    std::vector<uint8_t> badVertex;   // per `v` line: a coordinate is not a finite number
    std::vector<uint32_t> faceLines;  // 1-based line of each face tinyobjloader will report, in order
    std::vector<BigFace> bigFaces;    // faces of more than kMaxFaceCorners corners, in order
    size_t invalidFaces = 0;          // face lines removed (fewer than 3 corners)
    uint32_t firstInvalidLine = 0;
};

/// Normalises the OBJ text for tinyobjloader: LF line endings; relative and
/// zero indices made absolute or marked bad; trailing comments on face lines
/// dropped; line and point primitives (not rendered) and skin weights removed,
/// since tinyobjloader fails the whole file on some of their errors.
/// Line numbers are kept, so the face lines can be reported.
PreparedObj prepareObj(std::string_view text);

}  // namespace penumbra
