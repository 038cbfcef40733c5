// Typed exceptions: callers (and the CLI) tell bad input from bad parameters,
// resource limits and I/O failures by type; the message always names the problem.
#pragma once
#include <stdexcept>
#include <string>

namespace snvr {

struct Error : std::runtime_error {
    using std::runtime_error::runtime_error;
};
// Malformed or unusable input data (file contents, point sets).
struct InputError : Error {
    using Error::Error;
};
// A parameter out of range or inconsistent with others.
struct ParameterError : Error {
    using Error::Error;
};
// The run would need more memory (or other resources) than the machine has.
struct ResourceError : Error {
    using Error::Error;
};
// A file could not be opened, read or written.
struct IoError : Error {
    using Error::Error;
};

}  // namespace snvr
