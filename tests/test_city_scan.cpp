// The city block the sampler scans (shapes::city_scan) and writes as it makes it
// (write_point_stream, snvr-cl sample city): exactly the points asked for, in chunks,
// within the block, ground, walls and roofs, the same for a seed and not for another.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>

#include "cli_run.hpp"
#include "snvr/error.hpp"
#include "snvr/point_io.hpp"
#include "snvr/shapes.hpp"

using namespace snvr;
using namespace cli_testing;

TEST_CASE("city_scan: the points asked for, in chunks, ground, walls and roofs within the block, by seed") {
    PointSet all;
    std::size_t chunks = 0, largest = 0;
    shapes::city_scan(2500000, 7, [&](const PointSet& chunk) {
        ++chunks;
        largest = std::max(largest, chunk.size());
        all.insert(all.end(), chunk.begin(), chunk.end());
    });
    CHECK(all.size() == 2500000);
    CHECK(chunks == 3);  // 2^20 a chunk at most
    CHECK(largest == (1u << 20));
    std::size_t ground = 0, high = 0, wall = 0, outside = 0;
    for (const Vec3& p : all) {
        outside += !(std::abs(p[0]) <= 126.1 && std::abs(p[1]) <= 126.1 && p[2] >= -0.1 && p[2] <= 45.1);
        ground += std::abs(p[2]) < 0.05;
        high += p[2] > 6;
        wall += p[2] > 0.5 && p[2] < 5;  // below every roof: a wall seen from the street
    }
    CHECK(outside == 0);
    CHECK(ground > all.size() / 3);
    CHECK(high > all.size() / 10);
    CHECK(wall > all.size() / 20);
    PointSet first, again, other;  // a few points: every lap still stops on every street
    shapes::city_scan(1000, 7, [&](const PointSet& c) { first.insert(first.end(), c.begin(), c.end()); });
    shapes::city_scan(1000, 7, [&](const PointSet& c) { again.insert(again.end(), c.begin(), c.end()); });
    shapes::city_scan(1000, 8, [&](const PointSet& c) { other.insert(other.end(), c.begin(), c.end()); });
    CHECK(first.size() == 1000);
    CHECK(again == first);
    CHECK(other != first);
    CHECK_THROWS_AS(shapes::city_scan(0, 1, [](const PointSet&) {}), ParameterError);
}

TEST_CASE("write_point_stream: the count announced or nothing; snvr-cl sample city") {
    TempDir t;
    const std::string path = (t.path / "c.ply").string();
    write_point_stream(path, 5, "five", [](const std::function<void(const PointSet&)>& emit) {
        emit({{0, 0, 0}, {1, 0, 0}});
        emit({{0, 1, 0}, {0, 0, 1}, {1, 1, 1}});
    });
    CHECK(read_points(path).size() == 5);
    const auto wrong = [&](std::size_t made) {
        return [made](const std::function<void(const PointSet&)>& emit) { emit(PointSet(made, Vec3{0, 0, 0})); };
    };
    const std::string other = (t.path / "d.ply").string();
    CHECK_THROWS_AS(write_point_stream(other, 5, "", wrong(4)), IoError);
    CHECK_THROWS_AS(write_point_stream(other, 5, "", wrong(6)), IoError);
    CHECK_FALSE(std::filesystem::exists(other));
    CHECK_THROWS_AS(write_point_stream((t.path / "e.xyz").string(), 5, "", wrong(5)), IoError);

    const std::string city = (t.path / "city.ply").string();
    Run r = run("sample city --points 30000 --seed 3 -o " + city);
    CHECK(r.code == 0);
    CHECK(read_points(city).size() == 30000);
    r = run("sample city -o " + city);
    CHECK(r.code == 2);
    CHECK(r.output.find("needs --points") != std::string::npos);
    CHECK(run("sample sphere --points 10 -o " + city).code == 2);
    CHECK(run("sample city --points 10 -o " + (t.path / "city.xyz").string()).code == 2);
}
