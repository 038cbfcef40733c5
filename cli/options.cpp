#include "options.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <set>
#include <utility>

#include "report.hpp"
#include "snvr/error.hpp"
#include "snvr/formats.hpp"
#include "snvr/point_cloud.hpp"
#include "snvr/reconstruct.hpp"
#include "snvr/shell.hpp"

namespace cli {
namespace {

// ---------------------------------------------------------------- numbers

// True for "" too: callers decide whether a part may be empty.
bool digits(const std::string& s) {
    return std::all_of(s.begin(), s.end(), [](unsigned char ch) { return std::isdigit(ch) != 0; });
}

std::string without_sign(const std::string& s) {
    return (!s.empty() && (s[0] == '+' || s[0] == '-')) ? s.substr(1) : s;
}

// [+-] digits [. digits] [e [+-] digits] with digits on at least one side of the dot:
// plain decimal only, so "inf", "nan", hex and leading blanks (all taken by strtod)
// are refused.
bool is_decimal(const std::string& text) {
    const std::string s = without_sign(text);
    const std::size_t e = s.find_first_of("eE");
    const std::string mantissa = s.substr(0, e);
    const std::size_t dot = mantissa.find('.');
    const std::string whole = mantissa.substr(0, dot);
    const std::string fraction = dot == std::string::npos ? "" : mantissa.substr(dot + 1);
    if (!digits(whole) || !digits(fraction) || (whole.empty() && fraction.empty())) return false;
    if (e == std::string::npos) return true;
    const std::string exponent = without_sign(s.substr(e + 1));
    return !exponent.empty() && digits(exponent);
}

[[noreturn]] void bad_value(const std::string& option, const std::string& text, const char* expected) {
    throw UsageError("bad value '" + text + "' for " + option + ": expected " + expected);
}

// ---------------------------------------------------------------- option tables

// Called with the option's name and its value ("" for a flag).
using Apply = std::function<void(const std::string& option, const std::string& value)>;

struct Option {
    std::string name;     // "--steps"
    std::string alias;    // "-o", or empty
    std::string metavar;  // "N"; empty for a flag
    std::string help;     // '\n' starts a continuation line
    Apply apply;
    std::string heading = {};  // printed above this option in the help
};

struct Command {
    std::string usage;        // the synopsis after "Usage: "
    std::string description;  // a paragraph below it
    std::vector<Option> options;
    // Pairs that say the same thing two ways: at most one of each may be given.
    std::vector<std::pair<std::string, std::string>> exclusive;
    std::string epilogue;
};

template <class T>
T parse_as(const std::string& option, const std::string& text);
template <>
double parse_as<double>(const std::string& option, const std::string& text) { return parse_real(option, text); }
template <>
int parse_as<int>(const std::string& option, const std::string& text) { return parse_int(option, text); }
template <>
std::size_t parse_as<std::size_t>(const std::string& option, const std::string& text) {
    const int n = parse_int(option, text);
    if (n < 0) throw UsageError("bad value '" + text + "' for " + option + ": expected a count, 0 or more");
    return std::size_t(n);
}
template <>
std::string parse_as<std::string>(const std::string&, const std::string& text) { return text; }

// Parses the value into `target` (plain or optional), whatever its type.
template <class T>
Apply store(T& target) {
    return [&target](const std::string& option, const std::string& value) { target = parse_as<T>(option, value); };
}
template <class T>
Apply store(std::optional<T>& target) {
    return [&target](const std::string& option, const std::string& value) { target = parse_as<T>(option, value); };
}
Apply set_flag(bool& target) {
    return [&target](const std::string&, const std::string&) { target = true; };
}

// -h/--help is looked for before parsing (see wants_help); listed for the help text.
Option help_option(const std::string& heading = {}) {
    return {"--help", "-h", "", "show this help", [](const std::string&, const std::string&) {}, heading};
}

bool is_help(const std::string& token) { return token == "-h" || token == "--help"; }

bool wants_help(const std::vector<std::string>& args) {
    for (const std::string& a : args) {
        if (a == "--") return false;
        if (is_help(a)) return true;
    }
    return false;
}

const Option* find_option(const Command& command, const std::string& name) {
    for (const Option& o : command.options)
        if (o.name == name || (!o.alias.empty() && o.alias == name)) return &o;
    return nullptr;
}

// Applies every option and returns the positional arguments.
std::vector<std::string> parse(const Command& command, const std::vector<std::string>& args) {
    std::vector<std::string> positional;
    std::set<std::string> seen;
    for (std::size_t i = 0; i < args.size(); ++i) {
        const std::string& token = args[i];
        if (token == "--") {
            positional.insert(positional.end(), args.begin() + std::ptrdiff_t(i) + 1, args.end());
            break;
        }
        if (token.size() < 2 || token[0] != '-') {
            positional.push_back(token);
            continue;
        }
        const bool is_long = token.compare(0, 2, "--") == 0;
        const std::size_t eq = is_long ? token.find('=') : std::string::npos;
        const std::string name = token.substr(0, eq);
        const Option* option = find_option(command, name);
        if (!option) throw UsageError("unknown option '" + name + "'");
        if (!seen.insert(option->name).second) throw UsageError("option " + option->name + " given more than once");

        std::string value;
        if (option->metavar.empty()) {
            if (eq != std::string::npos) throw UsageError("option " + option->name + " takes no value");
        } else if (eq != std::string::npos) {
            value = token.substr(eq + 1);
            if (value.empty()) throw UsageError("option " + option->name + " needs a value (" + option->metavar + ")");
        } else {
            // A following "--option" means the value was forgotten; negative numbers
            // ("-1") still pass and are judged by the option itself.
            if (i + 1 >= args.size() || args[i + 1].compare(0, 2, "--") == 0 || args[i + 1].empty())
                throw UsageError("option " + option->name + " needs a value (" + option->metavar + ")");
            value = args[++i];
        }
        option->apply(option->name, value);
    }
    for (const auto& [a, b] : command.exclusive)
        if (seen.count(a) && seen.count(b)) throw UsageError("give either " + a + " or " + b + ", not both");
    return positional;
}

void print_help(const Command& command, std::ostream& out) {
    out << "Usage: " << command.usage << "\n\n" << command.description;
    const std::size_t column = 26;
    for (const Option& o : command.options) {
        if (!o.heading.empty()) out << "\n" << o.heading << ":\n";
        std::string left = "  " + (o.alias.empty() ? std::string("    ") : o.alias + ", ") + o.name;
        if (!o.metavar.empty()) left += " " + o.metavar;
        out << left;
        // Long synopses get the help on the next line.
        if (left.size() + 2 > column) out << "\n" << std::string(column, ' ');
        else out << std::string(column - left.size(), ' ');
        for (char ch : o.help) {
            out << ch;
            if (ch == '\n') out << std::string(column, ' ');
        }
        out << "\n";
    }
    if (!command.epilogue.empty()) out << "\n" << command.epilogue;
}

const char* const kExitCodes =
    "Exit status: 0 success; 1 failure (unreadable or bad input, I/O, out of memory,\n"
    "solver or device errors, an empty result); 2 usage error.\n";

Command reconstruct_command(ReconstructOptions& o) {
    snvr::ShellSettings& shell = o.shell;
    snvr::Parameters& p = shell.params;
    const snvr::Parameters defaults;
    auto precision = [&p](const std::string& option, const std::string& value) {
        if (value == "double") p.precision = snvr::Precision::Double;
        else if (value == "float") p.precision = snvr::Precision::Single;
        else bad_value(option, value, "double or float");
    };
    auto units = [&shell](const std::string& option, const std::string& value) {
        if (!snvr::millimetres_per_unit(value)) bad_value(option, value, "mm, cm, m or in");
        shell.units = value;
    };
    auto origin = [&shell](const std::string& option, const std::string& value) {
        if (value == "center") shell.origin = snvr::ShellOrigin::Centre;
        else if (value == "keep") shell.origin = snvr::ShellOrigin::Keep;
        else bad_value(option, value, "center or keep");
    };
    Command c;
    c.usage = "snvr-cl reconstruct INPUT -o OUTPUT [options]";
    // The formats from the library's table, so that the help lists what the readers take.
    c.description =
        "Reconstructs a thin closed shell (a narrow volume of thickness 2L around the\n"
        "points) by the Allen-Cahn method of Li et al. 2014 and writes it as a mesh.\n"
        "INPUT: points as " + snvr::format_extensions(snvr::FormatUse::ReadPoints) + ",\n"
        "or a mesh (with faces; thickened by its triangles) as " + snvr::format_extensions(snvr::FormatUse::ReadMesh) +
        ";\neach also gzipped (.gz). Lengths are in the points' (world) units unless\n"
        "the option says cells.\n";
    c.options = {
        {"--output", "-o", "FILE",
         "mesh to write (required): " + snvr::format_extensions(snvr::FormatUse::WriteMesh) +
             "\n(STL and PLY binary, 3MF in millimetres)",
         store(o.output), "Output"},
        {"--volume", "", "FILE",
         "also write the final phase field phi: " + snvr::format_extensions(snvr::FormatUse::WriteField),
         store(o.volume)},
        {"--report", "", "FILE", "also write the summary and the warnings as JSON (.json)", store(o.report)},
        {"--preview", "", "FILE",
         "also write a picture (.png): the shell shaded, and a cut\nthrough its middle across y (walls dark, voids white)",
         store(o.preview)},
        {"--units", "", "mm|cm|m|in",
         "the input's length unit (default mm); every output is written\nin millimetres, the unit slicers assume (3MF says so)",
         units},
        {"--scale", "", "S", "multiply the input's coordinates by S (default 1), e.g. to\nprint a model at 1:100",
         store(shell.scale)},
        {"--outliers", "", "FILE",
         "write the points dropped as outliers (.ply or .xyz)", store(o.outliers)},
        {"--keep-outliers", "", "",
         snvr::format_text("use every point: by default points far sparser than the\nsurface, lone points standing off a flat surface, and\nclusters of under %zu points (and under 1%%) that the shell\nwould leave apart as loose beads, are dropped",
             shell.outliers.min_cluster),
         [&shell](const std::string&, const std::string&) { shell.drop_outliers = false; }},
        {"--min-piece-volume", "", "V",
         "drop solid pieces (each with its cavities) of less volume,\nin the input's units cubed (default 0: keep all)",
         store(shell.pieces.min_volume)},
        {"--keep-largest", "", "N", "keep only the N largest solid pieces (default 0: all)",
         store(shell.pieces.keep_largest)},
        {"--origin", "", "center|keep",
         "center: shift the points by their box centre, rounded\n(shown in the summary), so that far coordinates such as\nsurvey data keep their precision in float32 STL and PLY;\nkeep: coordinates as read (default: keep, but center for\nSTL and 3MF where float32 would move the shell)",
         origin},
        {"--offset", "", "L",
         snvr::format_text("distance of each wall from the points, world units\n"
             "(default: the larger of %g voxels and the points' sampling gap)", defaults.offset_cells),
         store(p.offset), "Shell"},
        {"--offset-cells", "", "M",
         snvr::format_text("the default offset in voxels instead of %g (the sampling gap\nstill wins when larger)", defaults.offset_cells),
         store(p.offset_cells)},
        {"--thickness", "", "T", "wall-to-wall thickness 2L instead of --offset, world units", store(p.thickness)},
        {"--resolution", "", "N",
         snvr::format_text("cells on the longest axis of the padded box (default %d)", defaults.resolution), store(p.resolution),
         "Grid"},
        {"--voxel", "", "H", "voxel size instead of --resolution, world units", store(p.voxel)},
        {"--smoothing", "", "T",
         snvr::format_text("flow time in voxels squared: how much the surface is smoothed\n(default %g)", defaults.smoothing_cells),
         store(p.smoothing_cells), "Solver"},
        {"--dt-cells", "", "X", snvr::format_text("time step as dt / h^2 (default %g)", defaults.dt_cells), store(p.dt_cells)},
        {"--dt", "", "X", "time step in normalised units (longest side = 1) instead of\n--dt-cells", store(p.dt)},
        {"--steps", "", "N", "time steps (default: the flow time over the time step)", store(p.steps)},
        {"--tube-inner", "", "F",
         snvr::format_text("the flow keeps the surface at least (1 - F) x offset from the\npoints (default %g)", defaults.tube_inner),
         store(p.tube_inner)},
        {"--tube-outer", "", "F",
         snvr::format_text("...and at most (1 + F) x offset from them (default %g)", defaults.tube_outer), store(p.tube_outer)},
        {"--free-flow", "", "", "no tube: the paper's unconstrained flow", [&p](const std::string&, const std::string&) {
             p.keep_offset = false;
         }},
        {"--points-as-given", "", "",
         "no points added on the surface: none at a random sampling's holes\n(they show through the shell), none between points sparser than\nthe grid (their balls show)",
         [&p](const std::string&, const std::string&) { p.add_points = false; }},
        {"--eps-cells", "", "M", snvr::format_text("Allen-Cahn epsilon: the interface spans about M cells\n(default %g)", defaults.eps_cells),
         store(p.eps_cells)},
        {"--eps", "", "E", "Allen-Cahn epsilon instead of --eps-cells, world units", store(p.eps)},
        {"--xi-cells", "", "M", snvr::format_text("width xi of the initial tanh profile, in cells (default %g)", defaults.xi_cells),
         store(p.xi_cells)},
        {"--xi", "", "X", "xi instead of --xi-cells, world units", store(p.xi)},
        {"--tol", "", "X",
         snvr::format_text("RMS residual over the band at which a step's multigrid\nsolve stops (default %g: moves the surface ~1e-3 voxels)", defaults.tol),
         store(p.tol)},
        {"--max-cycles", "", "N",
         snvr::format_text("V-cycles per step at most; reaching it is a warning (default %d)", defaults.max_cycles),
         store(p.max_cycles)},
        {"--precision", "", "double|float", snvr::format_text("floating point type of the solver's fields (default %s)",
                 defaults.precision == snvr::Precision::Double ? "double" : "float"), precision},
        {"--device", "", "DEV",
         "auto | openmp | opencl | opencl:P:D | a name substring (default\n"
         "auto: an OpenCL GPU, else an OpenCL CPU, else OpenMP);\n"
         "see 'snvr-cl devices'",
         store(p.device)},
        {"--tile-cells", "", "N",
         "cut the grid into tiles of N cells a side (a multiple of 8), each\n"
         "run alone with a halo as wide as the flow reaches: the same shell\n"
         "(within 0.01 voxels), one tile's solver memory at a time (default\n"
         "0: the grid whole)",
         store(p.tile_cells), "Tiles"},
        {"--tile-halo-cells", "", "N",
         "the tiles' halo in cells (a multiple of 8) instead of the one\nderived from the flow", store(p.tile_halo_cells)},
        {"--temp-dir", "", "DIR",
         "where temporary files go: a .gz input is inflated there, and under\n"
         "--max-memory the points beyond it are kept there; unnamed files,\n"
         "gone when the run ends however it ends (default: the output's\n"
         "folder)",
         store(p.temp_dir)},
        {"--max-memory", "", "SIZE",
         "memory the run may take, e.g. 2G or 512M (powers of 1024): the\n"
         "points it files and all after; points beyond it are kept in files\n"
         "in --temp-dir (the same shell); the grid whole where it fits, else\n"
         "in the largest tiles that fit, else an error saying what does not\n"
         "(default: whole where the memory available holds it, else tiles)",
         [&p](const std::string& option, const std::string& value) { p.max_memory = parse_size(option, value); }},
        {"--fairing", "", "N",
         snvr::format_text("passes of Taubin smoothing over the mesh, 0 for the raw\nisosurface (default %d)", shell.fairing.passes),
         store(shell.fairing.passes), "Mesh"},
        {"--measure", "", "",
         "the check also measures the surface: distance to the points\nminus the offset, dihedral and normal noise (the check\ntakes about 1.4 times as long)",
         set_flag(shell.measure)},
        {"--quiet", "", "", "no progress or summary (errors and warnings still show)", set_flag(o.quiet),
         "Other"},
        help_option(),
    };
    c.exclusive = {{"--offset", "--thickness"}, {"--offset", "--offset-cells"}, {"--thickness", "--offset-cells"}, {"--resolution", "--voxel"}, {"--eps-cells", "--eps"},
                   {"--xi-cells", "--xi"}, {"--dt-cells", "--dt"}, {"--tube-inner", "--free-flow"}, {"--tube-outer", "--free-flow"}};
    c.epilogue = std::string(
                     "Options take '--opt value' or '--opt=value'. Progress, warnings and the summary\n"
                     "go to stderr. A mesh that is not closed, manifold and oriented, or that does\n"
                     "not enclose every point, is still written, with a warning.\n\n") +
                 kExitCodes;
    return c;
}

Command sample_command(SampleOptions& o) {
    Command c;
    c.usage = "snvr-cl sample SHAPE -o OUTPUT [--spacing S | --random N [--seed K]]";
    c.description =
        "Writes points sampled on an analytic test shape centred in the unit box, about\n"
        "S apart (exactly on the surface unless noisy):\n"
        "  sphere, half-sphere   radius 0.35 (half-sphere: open, z >= 0.5)\n"
        "  cube                  side 0.35\n"
        "  cylinder              radius and height 0.35, with caps\n"
        "  cone                  two cones joined at their base, radius 0.35, height 0.7\n"
        "  sheets                two parallel open squares, side 0.7, 0.06 apart in z\n"
        "  mobius                Moebius band, centre radius 0.3, width 0.25\n"
        "  helicoid              open helicoid, radius 0.35, pitch 0.2, 3 turns\n"
        "  noisy-sphere          the sphere plus Gaussian noise, sigma 0.3 S per axis (seed 1)\n"
        "  varying-sphere        the sphere, points per area falling 10x from the top pole\n"
        "                        (spacing S) to the bottom (spacing 3.16 S)\n"
        "  torus                 R 0.3, tube 0.12; give a large S to undersample it\n"
        "  lidar                 open bumpy terrain 0.7 x 0.7 scanned along lines of constant\n"
        "                        y 4 S apart, points S apart on a line, range noise 0.1 S\n"
        "and, with --points N instead of --spacing (in metres, written as it is made, never\n"
        "held whole, to a .ply):\n"
        "  city                  a 252 m city block of 4 x 4 lots of box buildings (6-45 m,\n"
        "                        by --seed) scanned from a car on every street (70%) and from\n"
        "                        the air: scan lines, occlusion gaps, 1 cm range noise\n";
    c.options = {
        {"--output", "-o", "FILE", "points to write (required): .ply (binary float) or .xyz (text)",
         store(o.output), "Options"},
        {"--spacing", "", "S", snvr::format_text("distance between neighbouring points (default %g)", o.spacing),
         store(o.spacing)},
        {"--random", "", "N",
         "N points drawn uniformly at random on the surface instead of\nspaced S apart (as a scanner's returns fall)",
         store(o.random)},
        {"--points", "", "N", "the city's returns (city only)", store(o.points)},
        {"--seed", "", "K", "the random draw's (or the city's) seed (default 1)", store(o.seed)},
        {"--outliers", "", "F",
         "add F times as many points uniform in the shape's box (the\npaper's Fig. 10 uses 0.05 to 0.15; default 0)",
         store(o.outliers)},
        help_option(),
    };
    c.exclusive = {{"--spacing", "--random"}, {"--points", "--random"}, {"--points", "--spacing"}, {"--points", "--outliers"}};
    c.epilogue = kExitCodes;
    return c;
}

Command devices_command() {
    Command c;
    c.usage = "snvr-cl devices";
    c.description = "Lists the devices that can run the solver and the ids that --device accepts.\n";
    c.options = {help_option("Options")};
    c.epilogue = kExitCodes;
    return c;
}

void require_extension(const std::string& what, const std::string& path, std::initializer_list<const char*> allowed) {
    const std::string ext = lower_extension(path);
    std::string list;
    for (const char* a : allowed) {
        if (ext == a) return;
        list += (list.empty() ? "" : ", ") + std::string(a);
    }
    throw UsageError(what + " '" + path + "' must end in one of " + list);
}

// A file for `use`: its extension one of a format the library's table says serves it.
void require_format(const std::string& what, const std::string& path, snvr::FormatUse use) {
    if (!snvr::format_serves(path, use))
        throw UsageError(what + " '" + path + "' must end in " + snvr::format_extensions(use));
}

std::string only_positional(const std::vector<std::string>& positional, const char* what) {
    if (positional.empty()) throw UsageError(std::string("missing ") + what);
    if (positional.size() > 1) throw UsageError("unexpected argument '" + positional[1] + "'");
    return positional[0];
}

}  // namespace

double parse_real(const std::string& option, const std::string& text) {
    if (!is_decimal(text)) bad_value(option, text, "a number");
    errno = 0;
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    if (end != text.c_str() + text.size() || errno == ERANGE || !std::isfinite(v))
        bad_value(option, text, "a finite number in the range of double");
    return v;
}

std::size_t parse_size(const std::string& option, const std::string& text) {
    std::string number = text, unit;
    while (!number.empty() && std::isalpha(static_cast<unsigned char>(number.back()))) {
        unit.insert(unit.begin(), char(std::toupper(static_cast<unsigned char>(number.back()))));
        number.pop_back();
    }
    const char* expected = "a size: bytes, or a number with K, M, G or T (powers of 1024: 2G, 512M, 1.5GiB)";
    if (!unit.empty() && unit.back() == 'B') unit.pop_back();
    if (unit.size() == 2 && unit[1] == 'I') unit.pop_back();
    const std::string units = "KMGT";
    const std::size_t power = unit.empty() ? 0 : unit.size() == 1 ? units.find(unit[0]) + 1 : 0;
    if (number.empty() || !is_decimal(number) || number[0] == '-' || number[0] == '+' ||
        (!unit.empty() && power == 0) || (!unit.empty() && power > units.size()))
        bad_value(option, text, expected);
    const double bytes = std::strtod(number.c_str(), nullptr) * std::pow(1024.0, double(power));
    if (!(bytes >= 1 && bytes < 9.2e18)) bad_value(option, text, expected);
    return std::size_t(bytes);
}

int parse_int(const std::string& option, const std::string& text) {
    const std::string unsigned_part = without_sign(text);
    if (unsigned_part.empty() || !digits(unsigned_part)) bad_value(option, text, "an integer");
    errno = 0;
    char* end = nullptr;
    const long v = std::strtol(text.c_str(), &end, 10);
    if (end != text.c_str() + text.size() || errno == ERANGE || v < INT_MIN || v > INT_MAX)
        bad_value(option, text, "an integer in the range of int");
    return int(v);
}

std::string lower_extension(const std::string& path) {
    // The same rule as the library's writers, so the early check agrees with them.
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char ch) { return char(std::tolower(ch)); });
    return ext;
}

std::optional<ReconstructOptions> parse_reconstruct(const std::vector<std::string>& args, std::ostream& help_out) {
    ReconstructOptions o;
    const Command command = reconstruct_command(o);
    if (wants_help(args)) {
        print_help(command, help_out);
        return std::nullopt;
    }
    o.input = only_positional(parse(command, args), "input file (the points)");
    if (o.input == "-")
        throw UsageError("points from standard input ('-') are not supported: give the points' file (its extension "
                         "names the format)");
    if (o.output.empty()) throw UsageError("missing output: give -o FILE");
    require_format("output", o.output, snvr::FormatUse::WriteMesh);
    if (!o.volume.empty()) require_format("--volume", o.volume, snvr::FormatUse::WriteField);
    if (!o.report.empty()) require_extension("--report", o.report, {".json"});
    if (!o.preview.empty()) require_extension("--preview", o.preview, {".png"});
    if (!o.outliers.empty()) require_extension("--outliers", o.outliers, {".ply", ".xyz"});
    if (!o.outliers.empty() && !o.shell.drop_outliers)
        throw UsageError("--outliers and --keep-outliers exclude each other");
    const double scale = o.shell.scale;
    if (!(scale >= snvr::ShellSettings::min_scale && scale <= snvr::ShellSettings::max_scale))
        bad_value("--scale", snvr::format_text("%g", scale), snvr::ShellSettings::scale_range);
    o.shell.written_as = o.output;
    o.shell.keep_field = !o.volume.empty();
    if (o.shell.params.temp_dir.empty()) {  // beside the output, where its own temporary goes
        const std::string folder = std::filesystem::path(o.output).parent_path().string();
        o.shell.params.temp_dir = folder.empty() ? "." : folder;
    }
    // Out-of-range values are the command line's fault, so a usage error, not a failure.
    try {
        o.shell.validate();
    } catch (const snvr::ParameterError& e) {
        throw UsageError(e.what());
    }
    return o;
}

std::optional<SampleOptions> parse_sample(const std::vector<std::string>& args, std::ostream& help_out) {
    SampleOptions o;
    const Command command = sample_command(o);
    if (wants_help(args)) {
        print_help(command, help_out);
        return std::nullopt;
    }
    o.shape = only_positional(parse(command, args), "shape name (see snvr-cl sample --help)");
    if (o.output.empty()) throw UsageError("missing output: give -o FILE");
    require_extension("output", o.output, {".ply", ".xyz"});
    if (!(o.spacing > 0)) throw UsageError(snvr::format_text("--spacing must be positive, got %g", o.spacing));
    if ((o.shape == "city") != (o.points > 0))
        throw UsageError(o.shape == "city" ? "the city needs --points N (its returns)" : "--points is the city's alone");
    if (o.shape == "city") require_extension("output", o.output, {".ply"});
    return o;
}

bool parse_devices(const std::vector<std::string>& args, std::ostream& help_out) {
    const Command command = devices_command();
    if (wants_help(args)) {
        print_help(command, help_out);
        return false;
    }
    const std::vector<std::string> positional = parse(command, args);
    if (!positional.empty()) throw UsageError("unexpected argument '" + positional[0] + "'");
    return true;
}

void print_main_help(std::ostream& out) {
    out << "snvr-cl: turns a 3D point cloud into a thin closed printable shell\n"
           "(Allen-Cahn surface embedding narrow volume reconstruction, Li et al. 2014).\n"
           "\n"
           "Usage:\n"
           "  snvr-cl reconstruct INPUT -o OUTPUT [options]   points -> shell mesh\n"
           "  snvr-cl devices                                 list the devices that can run the solver\n"
           "  snvr-cl sample SHAPE -o OUTPUT [--spacing S]    points on an analytic test shape\n"
           "  snvr-cl --help | --version\n"
           "\n"
           "Run 'snvr-cl COMMAND --help' for a command's options, defaults and units.\n"
           "\n"
        << kExitCodes;
}

}  // namespace cli
