// Typed exceptions: callers (and the CLI) tell bad input from bad parameters,
// resource limits and I/O failures by type; the message always names the problem.
#pragma once
#include <stdexcept>
#include <string>
#include <string_view>

namespace snvr {

// text with control characters (but newline and tab) and bytes that are not part of
// valid UTF-8 written as \xNN: a message may quote a file's contents or a path, and
// must print as it reads (no NUL cutting it short, no escape sequence for the terminal).
std::string printable(std::string_view text);

struct Error : std::runtime_error {
    explicit Error(const std::string& message) : std::runtime_error(printable(message)) {}
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
// The caller's progress callback asked the run to stop.
struct Cancelled : Error {
    using Error::Error;
};

}  // namespace snvr
