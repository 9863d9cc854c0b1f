// The one Penumbra error type: a code plus a message that names the file and
// the line or JSON path where that applies. Thrown at load, prepare or render
// time, never inside the per-ray path.
#pragma once

#include <stdexcept>
#include <string>

namespace penumbra {

enum class ErrorCode {
    InvalidArgument = 1,  // bad option or API argument
    FileNotFound = 2,
    ParseError = 3,       // malformed OBJ/MTL/JSON content
    InvalidScene = 4,     // scene content that cannot be rendered
    IoError = 5,          // reading or writing failed
    OutOfMemory = 6,
    Cancelled = 7,
    Embree = 8,           // the Embree device reported an error
    Internal = 9,
};

class Error : public std::runtime_error {
public:
    Error(ErrorCode code, const std::string& message) : std::runtime_error(message), code_(code) {}
    ErrorCode code() const { return code_; }

private:
    ErrorCode code_;
};

}  // namespace penumbra
