// Command-line parsing of snvr-cl: strict numbers, both `--opt value` and
// `--opt=value`, exclusive option pairs, and help generated from the same tables.
#pragma once
#include <optional>
#include <ostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "snvr/error.hpp"
#include "snvr/mesh.hpp"
#include "snvr/parameters.hpp"

namespace cli {

// A mistake on the command line: exit status 2 and a hint to read --help.
struct UsageError : std::runtime_error {
    explicit UsageError(const std::string& message) : std::runtime_error(snvr::printable(message)) {}
};

// The whole token must be a finite decimal number (or an integer), else UsageError
// naming the option and the value.
double parse_real(const std::string& option, const std::string& text);
int parse_int(const std::string& option, const std::string& text);

struct ReconstructOptions {
    std::string input, output, volume, report, outliers, preview;  // outliers: where the dropped points go
    bool keep_outliers = false;
    snvr::PieceFilter pieces;  // --min-piece-volume (input units cubed), --keep-largest
    snvr::Parameters params;
    snvr::MeshFairing fairing;
    // --origin center (true) or keep (false); unset: centred where a print format (STL,
    // 3MF) could not hold the coordinates faithfully, as survey scans need.
    std::optional<bool> centre_origin;
    std::string units = "mm";    // the input's length unit (--units)
    double scale = 1;            // --scale: input lengths times this
    bool measure = false;  // the check adds the surface figures (measure_quality, not measure_shell)
    bool quiet = false;
};

struct SampleOptions {
    std::string shape, output;
    double spacing = 0.005;
    double outliers = 0;  // fraction of random points added in the shape's box
};

// Each returns nullopt when -h/--help was given; the help then went to `help_out`.
std::optional<ReconstructOptions> parse_reconstruct(const std::vector<std::string>& args, std::ostream& help_out);
std::optional<SampleOptions> parse_sample(const std::vector<std::string>& args, std::ostream& help_out);
bool parse_devices(const std::vector<std::string>& args, std::ostream& help_out);

void print_main_help(std::ostream& out);

// ".stl" for "dir/Out.STL"; empty when there is none.
std::string lower_extension(const std::string& path);

}  // namespace cli
