// Command-line parsing of snvr-cl: strict numbers, both `--opt value` and
// `--opt=value`, exclusive option pairs, and help generated from the same tables.
#pragma once
#include <optional>
#include <ostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "snvr/error.hpp"
#include "snvr/shell.hpp"

namespace cli {

// A mistake on the command line: exit status 2 and a hint to read --help.
struct UsageError : std::runtime_error {
    explicit UsageError(const std::string& message) : std::runtime_error(snvr::printable(message)) {}
};

// The whole token must be a finite decimal number (or an integer), else UsageError
// naming the option and the value.
double parse_real(const std::string& option, const std::string& text);
int parse_int(const std::string& option, const std::string& text);
// Bytes: a number with an optional K, M, G or T (powers of 1024), "i" and "B" allowed.
std::size_t parse_size(const std::string& option, const std::string& text);

struct ReconstructOptions {
    std::string input, output, volume, report, outliers, preview;  // outliers: where the dropped points go
    // What the options say of the shell, as the library takes it: lengths in the input's
    // units (--units, --scale), written_as the output, keep_field when --volume is given.
    snvr::ShellSettings shell;
    bool quiet = false;
};

struct SampleOptions {
    std::string shape, output;
    double spacing = 0.005;
    double outliers = 0;  // fraction of random points added in the shape's box
    std::size_t random = 0;  // points drawn at random on the surface instead of spaced; 0: spaced
    std::uint64_t seed = 1;
    std::size_t points = 0;  // the city's returns
};

// Each returns nullopt when -h/--help was given; the help then went to `help_out`.
std::optional<ReconstructOptions> parse_reconstruct(const std::vector<std::string>& args, std::ostream& help_out);
std::optional<SampleOptions> parse_sample(const std::vector<std::string>& args, std::ostream& help_out);
bool parse_devices(const std::vector<std::string>& args, std::ostream& help_out);

void print_main_help(std::ostream& out);

// ".stl" for "dir/Out.STL"; empty when there is none.
std::string lower_extension(const std::string& path);

}  // namespace cli
