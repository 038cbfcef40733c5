// mesh_distance A B [--voxel H]: how far two meshes of one surface are from each other
// (a tiled run's and a whole one's): the largest and RMS distance from each vertex of
// either to the nearest vertex of the other, in world units and, with --voxel, in voxels.
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

#include "snvr/mesh_io.hpp"
#include "snvr/quality.hpp"

int main(int argc, char** argv) {
    if (argc != 3 && !(argc == 5 && std::string(argv[3]) == "--voxel")) {
        std::fprintf(stderr, "usage: mesh_distance A B [--voxel H]\n");
        return 2;
    }
    try {
        const snvr::Mesh a = snvr::read_mesh(argv[1]), b = snvr::read_mesh(argv[2]);
        const snvr::VertexDistance d = snvr::vertex_distance(a, b);
        const double h = argc == 5 ? std::atof(argv[4]) : 0;
        std::printf("vertices %zu and %zu; max %.6g, RMS %.6g", a.vertices.size(), b.vertices.size(), d.max, d.rms);
        if (h > 0) std::printf(" (max %.4g, RMS %.4g voxels)", d.max / h, d.rms / h);
        std::printf("\n");
    } catch (const std::exception& e) {
        std::fprintf(stderr, "mesh_distance: %s\n", e.what());
        return 1;
    }
}
