#include "core/error.h"

namespace pnb {

// Out of line: the key function, so the type's RTTI lives in the library once.
Error::~Error() = default;

const char* errorCodeName(ErrorCode code) noexcept {
    switch (code) {
        case ErrorCode::InvalidArgument: return "invalid argument";
        case ErrorCode::FileNotFound: return "file not found";
        case ErrorCode::ParseError: return "parse error";
        case ErrorCode::InvalidScene: return "invalid scene";
        case ErrorCode::IoError: return "I/O error";
        case ErrorCode::OutOfMemory: return "out of memory";
        case ErrorCode::Cancelled: return "cancelled";
        case ErrorCode::Embree: return "Embree error";
        case ErrorCode::Internal: return "internal error";
    }
    return "unknown error";
}

}  // namespace pnb
