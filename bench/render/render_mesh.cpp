// render_mesh: a PNG preview of a mesh file, flat shaded so faceting stays visible.
//   render_mesh MESH -o out.png [--size N | --size WxH] [--view x,y,z] [--up x,y,z]
//               [--zoom Z --center u,v] [--perspective DEGREES] [--smooth]
// Exit status: 0 success, 1 failure, 2 usage.
#include <cstdio>
#include <exception>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "snvr/mesh_io.hpp"
#include "snvr/render.hpp"

namespace {

constexpr const char* kUsage =
    "usage: render_mesh MESH -o out.png [--size N | --size WxH] [--view x,y,z] [--up x,y,z]\n"
    "                   [--zoom Z --center u,v] [--perspective DEGREES] [--smooth]\n"
    "  --view   direction from the mesh towards the camera (default 0.55,0.45,1: front-right-above, +y up)\n"
    "  --zoom   magnify the full view Z times around --center (normalised u right, v down; default 0.5,0.5)\n";

struct UsageError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// Comma- (or 'x'-) separated numbers, exactly `count` of them.
std::vector<double> numbers(const std::string& flag, std::string text, std::size_t count, char separator) {
    for (char& ch : text)
        if (ch == separator) ch = ' ';
    std::istringstream in(text);
    std::vector<double> out;
    double v;
    while (in >> v) out.push_back(v);
    if (!in.eof() || out.size() != count)
        throw UsageError(flag + " expects " + std::to_string(count) + " numbers separated by '" + separator + "'");
    return out;
}

}  // namespace

int main(int argc, char** argv) {
    std::string input, output;
    snvr::render::RenderView view;
    try {
        for (int i = 1; i < argc; ++i) {
            const std::string arg = argv[i];
            const auto value = [&]() -> std::string {
                if (i + 1 >= argc) throw UsageError(arg + " needs a value");
                return argv[++i];
            };
            if (arg == "-h" || arg == "--help") {
                std::fputs(kUsage, stdout);
                return 0;
            } else if (arg == "-o") output = value();
            else if (arg == "--size") {
                const std::string v = value();
                const bool two = v.find('x') != std::string::npos;
                const auto n = numbers(arg, v, two ? 2 : 1, 'x');
                view.width = int(n[0]), view.height = int(n[two ? 1 : 0]);
                if (n[0] != view.width || n[two ? 1 : 0] != view.height) throw UsageError("--size expects whole numbers");
            } else if (arg == "--view") {
                const auto n = numbers(arg, value(), 3, ',');
                view.direction = {n[0], n[1], n[2]};
            } else if (arg == "--up") {
                const auto n = numbers(arg, value(), 3, ',');
                view.up = {n[0], n[1], n[2]};
            } else if (arg == "--zoom") view.zoom = numbers(arg, value(), 1, ',')[0];
            else if (arg == "--center") {
                const auto n = numbers(arg, value(), 2, ',');
                view.center = {n[0], n[1]};
            } else if (arg == "--perspective") view.perspective_degrees = numbers(arg, value(), 1, ',')[0];
            else if (arg == "--smooth") view.smooth = true;
            else if (!arg.empty() && arg[0] == '-') throw UsageError("unknown option " + arg);
            else if (input.empty()) input = arg;
            else throw UsageError("more than one input file");
        }
        if (input.empty() || output.empty()) throw UsageError("a mesh file and -o out.png are required");
    } catch (const UsageError& e) {
        std::fprintf(stderr, "render_mesh: %s\n%s", e.what(), kUsage);
        return 2;
    }
    try {
        const snvr::Mesh mesh = snvr::read_mesh(input);
        snvr::render::render_png(mesh, output, view);
        std::printf("render_mesh: %s (%zu triangles) -> %s (%dx%d)\n", input.c_str(), mesh.triangles.size(),
                    output.c_str(), view.width, view.height);
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "render_mesh: error: %s\n", e.what());
        return 1;
    }
}
