// city_scan (shapes.hpp): a city block scanned from the street and from the air, point
// by point as the scanners would return them, handed out in chunks.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "snvr/error.hpp"
#include "snvr/shapes.hpp"

namespace snvr::shapes {

namespace {

constexpr double kPi = 3.14159265358979323846;
// The block, in metres: 4 x 4 lots of 48 m between streets 12 m wide, centred on 0.
constexpr int kLots = 4;
constexpr double kLot = 48, kStreet = 12, kPitch = kLot + kStreet;
constexpr double kSide = kLots * kPitch + kStreet;  // from street edge to street edge
constexpr double kMobileHeight = 2.5, kMobileRange = 80, kRangeNoise = 0.01;
constexpr double kFlightHeight = 300, kSwath = 30 * kPi / 180, kFlightGap = 30;
constexpr int kFan = 900;            // rays a profile (0.4 degrees apart)
constexpr double kMobileShare = 0.7;  // of the returns; the rest from the air
constexpr std::size_t kChunk = 1 << 20;

struct Box {
    double lo[3], hi[3];
};

// One or two buildings a lot, each a box within it (2-6 m from its edges), 6-45 m high.
std::vector<Box> buildings(std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0, 1);
    std::vector<Box> out;
    for (int i = 0; i < kLots; ++i)
        for (int j = 0; j < kLots; ++j) {
            const double x0 = -kSide / 2 + kStreet + i * kPitch, y0 = -kSide / 2 + kStreet + j * kPitch;
            const int count = u(rng) < 0.5 ? 1 : 2;
            for (int b = 0; b < count; ++b) {
                // Two buildings split the lot along x.
                const double from = x0 + (count == 2 ? b * kLot / 2 : 0), span = count == 2 ? kLot / 2 : kLot;
                Box box;
                box.lo[0] = from + 2 + 4 * u(rng);
                box.hi[0] = from + span - 2 - 4 * u(rng);
                box.lo[1] = y0 + 2 + 4 * u(rng);
                box.hi[1] = y0 + kLot - 2 - 4 * u(rng);
                box.lo[2] = 0;
                box.hi[2] = 6 + 39 * u(rng);
                out.push_back(box);
            }
        }
    return out;
}

// The nearest hit along o + t d (t > 0, at most `range`): the ground (z = 0) or a
// building; false for none (the sky, or beyond range).
bool first_hit(const std::vector<Box>& boxes, const Vec3& o, const Vec3& d, double range, double& t_hit) {
    t_hit = range;
    bool hit = false;
    if (d[2] < 0) {
        const double t = -o[2] / d[2];
        if (t > 0 && t < t_hit && std::abs(o[0] + t * d[0]) <= kSide / 2 && std::abs(o[1] + t * d[1]) <= kSide / 2) {
            t_hit = t;
            hit = true;
        }
    }
    for (const Box& b : boxes) {
        double t0 = 0, t1 = t_hit;
        for (int a = 0; a < 3 && t0 <= t1; ++a) {
            if (d[a] == 0) {
                if (o[a] < b.lo[a] || o[a] > b.hi[a]) t0 = t1 + 1;
                continue;
            }
            double ta = (b.lo[a] - o[a]) / d[a], tb = (b.hi[a] - o[a]) / d[a];
            if (ta > tb) std::swap(ta, tb);
            t0 = std::max(t0, ta);
            t1 = std::min(t1, tb);
        }
        if (t0 <= t1 && t0 > 0 && t0 < t_hit) {
            t_hit = t0;
            hit = true;
        }
    }
    return hit;
}

// Hands the points out in chunks of at most kChunk.
class Emitter {
public:
    Emitter(std::size_t count, const std::function<void(const PointSet&)>& emit) : left_(count), emit_(emit) {}
    bool done() const { return left_ == 0; }
    void add(const Vec3& p) {
        if (left_ == 0) return;
        chunk_.push_back(p);
        --left_;
        if (chunk_.size() == kChunk || left_ == 0) {
            emit_(chunk_);
            chunk_.clear();
        }
    }

private:
    std::size_t left_;
    const std::function<void(const PointSet&)>& emit_;
    PointSet chunk_;
};

// Where lap `lap` starts within the first `step` (the golden ratio's sequence: the laps'
// stops interleave evenly).
double lap_start(int lap, double step) {
    const double golden = 0.6180339887498949;
    const double f = (lap + 0.5) * golden;
    return -kSide / 2 + (f - std::floor(f)) * step;
}

// The street scanner: along every street's centre line in turn, lap after lap (each lap
// starting a little further on), a fan of rays in the plane across the street at each stop.
void scan_streets(const std::vector<Box>& boxes, std::size_t count, double step, std::mt19937_64& rng, Emitter& out) {
    std::normal_distribution<double> noise(0, kRangeNoise);
    std::size_t made = 0;
    for (int lap = 0; made < count; ++lap)
        for (int street = 0; street <= 2 * kLots + 1 && made < count; ++street) {
            const bool along_x = street <= kLots;
            const double centre = -kSide / 2 + kStreet / 2 + (street % (kLots + 1)) * kPitch;
            for (double s = lap_start(lap, step); s < kSide / 2 && made < count; s += step) {
                const Vec3 o = along_x ? Vec3{s, centre, kMobileHeight} : Vec3{centre, s, kMobileHeight};
                for (int r = 0; r < kFan && made < count; ++r) {
                    const double a = 2 * kPi * (r + 0.5) / kFan;
                    const Vec3 d = along_x ? Vec3{0, std::cos(a), std::sin(a)} : Vec3{std::cos(a), 0, std::sin(a)};
                    double t;
                    if (!first_hit(boxes, o, d, kMobileRange, t)) continue;
                    t += noise(rng);
                    out.add({o[0] + t * d[0], o[1] + t * d[1], o[2] + t * d[2]});
                    ++made;
                }
            }
        }
}

// The airborne scanner: flight lines along y every kFlightGap, rays across the track
// within the swath, lap after lap offset along the track.
void scan_air(const std::vector<Box>& boxes, std::size_t count, double step, std::mt19937_64& rng, Emitter& out) {
    std::normal_distribution<double> noise(0, kRangeNoise);
    const int across = 600;
    std::size_t made = 0;
    for (int lap = 0; made < count; ++lap)
        for (double x = -kSide / 2; x <= kSide / 2 && made < count; x += kFlightGap)
            for (double y = lap_start(lap, step); y < kSide / 2 && made < count; y += step)
                for (int r = 0; r < across && made < count; ++r) {
                    const double a = kSwath * (2 * (r + 0.5) / across - 1);
                    const Vec3 o{x, y, kFlightHeight}, d{std::sin(a), 0, -std::cos(a)};
                    double t;
                    if (!first_hit(boxes, o, d, 2 * kFlightHeight, t)) continue;
                    t += noise(rng);
                    out.add({o[0] + t * d[0], o[1] + t * d[1], o[2] + t * d[2]});
                    ++made;
                }
}

}  // namespace

void city_scan(std::size_t count, std::uint64_t seed, const std::function<void(const PointSet&)>& emit) {
    if (count == 0) throw ParameterError("shapes: a city scan needs at least one point");
    const std::vector<Box> boxes = buildings(seed);
    std::mt19937_64 rng(seed ^ 0x9e3779b97f4a7c15ull);
    Emitter out(count, emit);
    const std::size_t street = std::size_t(std::llround(kMobileShare * double(count))), air = count - street;
    // Stops so that one lap gives about the points asked for (about half the rays return).
    const double route = 2.0 * (kLots + 1) * kSide;
    // Every lap stops at least once a street (and returns points: the ground is below).
    const double street_step = std::clamp(route * kFan * 0.5 / std::max<double>(1, double(street)), 1e-4, kSide / 2);
    const double flights = std::floor(kSide / kFlightGap) + 1;
    const double air_step = std::clamp(flights * kSide * 600 * 0.95 / std::max<double>(1, double(air)), 1e-4, kSide / 2);
    scan_streets(boxes, street, street_step, rng, out);
    scan_air(boxes, air, air_step, rng, out);
}

}  // namespace snvr::shapes
