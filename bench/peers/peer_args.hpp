// The peers' shared command line: POINTS -o OUT --voxel H --offset L, plus options of
// their own (peer_args.hpp; one parser, so they take the same words alike).
#pragma once
#include <functional>
#include <stdexcept>
#include <string>

namespace snvr::peers {

struct PeerArgs {
    std::string points, out;
    double voxel = 0, offset = 0;
};

struct UsageError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

inline double parse_number(const std::string& flag, const std::string& text) {
    try {
        std::size_t used = 0;
        const double v = std::stod(text, &used);
        if (used == text.size()) return v;
    } catch (const std::exception&) {
    }
    throw UsageError(flag + " expects a number, got '" + text + "'");
}

// Parses the shared words; `other(flag, value)` takes any other option with a value and
// returns whether it knew it. Throws UsageError naming the problem.
inline PeerArgs parse_peer_args(int argc, char** argv,
                                const std::function<bool(const std::string&, const std::string&)>& other = {}) {
    PeerArgs a;
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        const auto value = [&]() -> std::string {
            if (i + 1 >= argc) throw UsageError(arg + " needs a value");
            return argv[++i];
        };
        if (arg == "-o") a.out = value();
        else if (arg == "--voxel") a.voxel = parse_number(arg, value());
        else if (arg == "--offset") a.offset = parse_number(arg, value());
        else if (!arg.empty() && arg[0] == '-') {
            if (!other || !other(arg, value())) throw UsageError("unknown option " + arg);
        } else if (a.points.empty()) a.points = arg;
        else throw UsageError("more than one input file");
    }
    if (a.points.empty() || a.out.empty()) throw UsageError("an input file and -o OUT are required");
    if (!(a.voxel > 0) || !(a.offset > 0)) throw UsageError("--voxel and --offset are required and positive");
    return a;
}

}  // namespace snvr::peers
