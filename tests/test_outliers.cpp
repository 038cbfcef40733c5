// Outliers dropped before the run: the paper's Fig. 10 sphere with random points in its
// box comes back as its two-sheet shell, and real scans lose nothing (or next to nothing).
#include <doctest/doctest.h>

#include <string>

#include "snvr/snvr.hpp"

using namespace snvr;

namespace {

MeshReport shell_report(const PointSet& points, int resolution) {
    Parameters p;
    p.resolution = resolution;
    p.device = "openmp";
    const Result r = reconstruct(points, p);
    return check_mesh(shell_mesh(r, points));
}

}  // namespace

TEST_CASE("a sphere with 5% and 15% random points in its box: the two-sheet shell") {
    const PointSet clean = shapes::sphere({0.5, 0.5, 0.5}, 0.35, 0.01);
    Parameters p;
    p.resolution = 96;
    for (double fraction : {0.05, 0.15}) {
        CAPTURE(fraction);
        const PointSet noisy = shapes::with_outliers(clean, fraction, 7);
        const OutlierSplit split = split_outliers(noisy, p);
        const std::size_t added = noisy.size() - clean.size();
        MESSAGE(fraction << ": " << split.outliers.size() << " of " << added << " random points dropped");
        CHECK(split.outliers.size() >= added / 2);           // most of them
        CHECK(split.kept.size() + split.outliers.size() == noisy.size());
        CHECK(split.link > 0);
        // The sphere's own points are never dropped (they come first in `noisy`).
        CHECK(std::equal(clean.begin(), clean.end(), split.kept.begin()));
        const MeshReport kept = shell_report(split.kept, 96);
        CHECK(kept.closed());
        CHECK(kept.solids == 1);
        CHECK(kept.components == 2);  // the outer sheet and the inner one
        // Without the split the random points fill the sphere with beads and bubbles.
        const MeshReport all = shell_report(noisy, 96);
        CHECK(all.components > 2);
    }
}

TEST_CASE("real scans and clean shapes keep their points") {
    Parameters p;
    p.resolution = 128;
    for (const char* scan : {"bunny", "igea", "armadillo", "cactus", "distcap", "dragon"}) {
        CAPTURE(scan);
        const PointSet points = read_points(std::string(SNVR_DATA_DIR) + "/" + scan + ".ply");
        CHECK(split_outliers(points, p).outliers.empty());
    }
    // The horse has 15 points (0.03%) in small groups 4-7 spacings from the rest: sparse
    // enough to go (a shell keeps them, but they set nothing apart).
    const PointSet horse = read_points(std::string(SNVR_DATA_DIR) + "/horse.ply");
    CHECK(split_outliers(horse, p).outliers.size() <= horse.size() / 1000);
    for (const char* shape : {"half-sphere", "sheets", "varying-sphere", "lidar", "torus"}) {
        CAPTURE(shape);
        CHECK(split_outliers(shapes::by_name(shape, 0.01), p).outliers.empty());
    }
    // Too few points to tell: all kept.
    CHECK(split_outliers(PointSet{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {9, 9, 9}}, p).outliers.empty());
}
