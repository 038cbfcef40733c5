// The processes of an MPI job as a tiled run's scheduler (processes.hpp).
#include <mpi.h>

#include <algorithm>
#include <array>
#include <climits>
#include <cstdlib>
#include <list>
#include <cstdint>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "processes.hpp"
#include "snvr/error.hpp"

namespace cli {

namespace {

bool started = false;

void check(int code, const char* what) {
    if (code != MPI_SUCCESS) throw snvr::Error(std::string("MPI: ") + what + " failed");
}

int as_count(std::size_t n, const char* what) {
    if (n > std::size_t(INT_MAX)) throw snvr::ResourceError(std::string("MPI: ") + what + " too large to send at once");
    return int(n);
}

// Long arrays go in parts: MPI counts in int.
constexpr std::size_t kPart = std::size_t(1) << 28;
template <class T>
void send_parts(const T* data, std::size_t n, MPI_Datatype type, int to, int tag, const char* what) {
    const std::int64_t count = std::int64_t(n);
    check(MPI_Send(&count, 1, MPI_INT64_T, to, tag, MPI_COMM_WORLD), what);
    for (std::size_t at = 0; at < n; at += kPart)
        check(MPI_Send(data + at, int(std::min(kPart, n - at)), type, to, tag, MPI_COMM_WORLD), what);
}
template <class T>
void send_parts(const std::vector<T>& data, MPI_Datatype type, int to, int tag, const char* what) {
    send_parts(data.data(), data.size(), type, to, tag, what);
}
// The count first, then the parts into room(count).
template <class T, class Room>
void receive_parts_into(MPI_Datatype type, int from, int tag, const char* what, const Room& room) {
    std::int64_t count = 0;
    check(MPI_Recv(&count, 1, MPI_INT64_T, from, tag, MPI_COMM_WORLD, MPI_STATUS_IGNORE), what);
    const std::size_t n = static_cast<std::size_t>(count);
    T* data = room(n);
    for (std::size_t at = 0; at < n; at += kPart)
        check(MPI_Recv(data + at, int(std::min(kPart, n - at)), type, from, tag, MPI_COMM_WORLD, MPI_STATUS_IGNORE),
              what);
}
template <class T>
std::vector<T> receive_parts(MPI_Datatype type, int from, int tag, const char* what) {
    std::vector<T> data;
    receive_parts_into<T>(type, from, tag, what, [&data](std::size_t n) {
        data.resize(n);
        return data.data();
    });
    return data;
}

enum Tag { kHeader = 1, kTable, kStored, kFigures, kPoints, kCheckShare, kChecked, kUpsample, kUpsampled, kBytes };
constexpr int kHeaderSize = 8;

// A worker's results go out as it goes on (MPI_Isend), each kept until sent() has waited
// for the root to take them; the root takes whichever comes in first.
class MpiTiles : public snvr::TileScheduler {
public:
    int processes() const override { return process_count(); }
    int rank() const override { return process_rank(); }

    void send(snvr::TileResult result) override {
        outgoing_.push_back({std::move(result), {}});
        Outgoing& out = outgoing_.back();
        const snvr::Field& f = out.result.field;
        const bool single = f.precision == snvr::Precision::Single;
        const std::size_t stored = single ? f.stored_f32().size() : f.stored_f64().size();
        out.header = {std::int64_t(out.result.tile),          f.nx,
                      f.ny,
                      f.nz,
                      single ? 1 : 0,
                      std::int64_t(f.brick_table().size()), std::int64_t(stored),
                      std::int64_t(out.result.figures.size())};
        const auto post = [&](const void* data, std::size_t n, MPI_Datatype type, int tag) {
            requests_.emplace_back();
            check(MPI_Isend(data, as_count(n, "a tile"), type, 0, tag, MPI_COMM_WORLD, &requests_.back()), "sending a tile");
        };
        post(out.header.data(), out.header.size(), MPI_INT64_T, kHeader);
        post(f.brick_table().data(), f.brick_table().size(), MPI_UINT32_T, kTable);
        if (single) post(f.stored_f32().data(), stored, MPI_FLOAT, kStored);
        else post(f.stored_f64().data(), stored, MPI_DOUBLE, kStored);
        post(out.result.figures.data(), out.result.figures.size(), MPI_DOUBLE, kFigures);
    }

    void sent() override {
        check(MPI_Waitall(int(requests_.size()), requests_.data(), MPI_STATUSES_IGNORE), "sending the tiles");
        requests_.clear();
        outgoing_.clear();
    }

    bool waiting() override {
        int flag = 0;
        check(MPI_Iprobe(MPI_ANY_SOURCE, kHeader, MPI_COMM_WORLD, &flag, MPI_STATUS_IGNORE), "looking for tiles");
        return flag != 0;
    }

    snvr::TileResult receive() override {
        MPI_Status status;
        check(MPI_Probe(MPI_ANY_SOURCE, kHeader, MPI_COMM_WORLD, &status), "waiting for a tile");
        const int from = status.MPI_SOURCE;
        std::int64_t header[kHeaderSize];
        check(MPI_Recv(header, kHeaderSize, MPI_INT64_T, from, kHeader, MPI_COMM_WORLD, MPI_STATUS_IGNORE),
              "receiving a tile");
        std::vector<std::uint32_t> table(static_cast<std::size_t>(header[5]));
        check(MPI_Recv(table.data(), int(table.size()), MPI_UINT32_T, from, kTable, MPI_COMM_WORLD, MPI_STATUS_IGNORE),
              "receiving a tile");
        snvr::TileResult r;
        r.tile = std::size_t(header[0]);
        const int nx = int(header[1]), ny = int(header[2]), nz = int(header[3]);
        const auto field = [&](auto real, MPI_Datatype type) {
            std::vector<decltype(real)> stored(static_cast<std::size_t>(header[6]));
            check(MPI_Recv(stored.data(), int(stored.size()), type, from, kStored, MPI_COMM_WORLD, MPI_STATUS_IGNORE),
                  "receiving a tile");
            return snvr::Field::from_bricks(nx, ny, nz, std::move(table), std::move(stored));
        };
        r.field = header[4] ? field(0.0f, MPI_FLOAT) : field(0.0, MPI_DOUBLE);
        r.figures.resize(static_cast<std::size_t>(header[7]));
        check(MPI_Recv(r.figures.data(), int(r.figures.size()), MPI_DOUBLE, from, kFigures, MPI_COMM_WORLD,
                       MPI_STATUS_IGNORE),
              "receiving a tile");
        return r;
    }

    std::vector<int> most(const std::vector<int>& mine) override {
        std::vector<int> out(mine.size());
        check(MPI_Allreduce(mine.data(), out.data(), int(mine.size()), MPI_INT, MPI_MAX, MPI_COMM_WORLD),
              "agreeing on the V-cycles");
        return out;
    }

    void share(std::vector<double>& plan, std::vector<int>& owners) override {
        std::int64_t sizes[2] = {std::int64_t(plan.size()), std::int64_t(owners.size())};
        check(MPI_Bcast(sizes, 2, MPI_INT64_T, 0, MPI_COMM_WORLD), "sharing the plan");
        plan.resize(std::size_t(sizes[0]));
        owners.resize(std::size_t(sizes[1]));
        check(MPI_Bcast(plan.data(), as_count(plan.size(), "the plan"), MPI_DOUBLE, 0, MPI_COMM_WORLD), "sharing the plan");
        check(MPI_Bcast(owners.data(), as_count(owners.size(), "the tiles"), MPI_INT, 0, MPI_COMM_WORLD),
              "sharing the tiles");
    }

    void give_upsampling(int process, const snvr::UpsampleShare& share) override {
        const double figures[7] = {share.spacing,         double(share.begin),   double(share.end),    share.points_frame[0],
                                   share.points_frame[1], share.points_frame[2], share.points_frame[3]};
        check(MPI_Send(figures, 7, MPI_DOUBLE, process, kUpsample, MPI_COMM_WORLD), "sending the points to add");
        if (share.spacing > 0) give_points(process, share.origin, share.points.data(), share.points.size());
    }

    std::vector<double> take_upsampled(int process) override {
        return receive_parts<double>(MPI_DOUBLE, process, kUpsampled, "receiving the points added");
    }

    snvr::UpsampleShare upsampling() override {
        snvr::UpsampleShare share;
        double figures[7] = {0, 0, 0, 0, 0, 0, 0};
        check(MPI_Recv(figures, 7, MPI_DOUBLE, 0, kUpsample, MPI_COMM_WORLD, MPI_STATUS_IGNORE),
              "receiving the points to add");
        std::copy(figures + 3, figures + 7, share.points_frame.begin());
        share.spacing = figures[0];
        share.begin = std::uint64_t(figures[1]);
        share.end = std::uint64_t(figures[2]);
        if (share.spacing > 0) take_points_into(share.origin, share.points);
        return share;
    }

    void send_upsampled(const std::vector<double>& xyz) override {
        send_parts(xyz, MPI_DOUBLE, 0, kUpsampled, "sending the points added");
    }

    void give_points(int process, const snvr::Vec3& origin, const float* xyz, std::size_t floats) override {
        check(MPI_Send(origin.data(), 3, MPI_DOUBLE, process, kPoints, MPI_COMM_WORLD), "sending the points");
        send_parts(xyz, floats, MPI_FLOAT, process, kPoints, "sending the points");
    }

    void take_points(snvr::Vec3& origin, const std::function<float*(std::size_t)>& room) override {
        check(MPI_Recv(origin.data(), 3, MPI_DOUBLE, 0, kPoints, MPI_COMM_WORLD, MPI_STATUS_IGNORE), "receiving the points");
        receive_parts_into<float>(MPI_FLOAT, 0, kPoints, "receiving the points", room);
    }

    void send_bytes(int process, const void* bytes, std::size_t size) override {
        send_parts(static_cast<const char*>(bytes), size, MPI_BYTE, process, kBytes, "sending the points' tree or the depth guard's search");
    }

    void receive_bytes(int process, const std::function<void*(std::size_t)>& room) override {
        receive_parts_into<char>(MPI_BYTE, process, kBytes, "receiving the points' tree or the depth guard's search",
                                 [&room](std::size_t n) { return static_cast<char*>(room(n)); });
    }

    void sum(std::vector<std::uint64_t>& values) override {
        for (std::size_t at = 0; at < values.size(); at += kPart)
            check(MPI_Allreduce(MPI_IN_PLACE, values.data() + at, int(std::min(kPart, values.size() - at)), MPI_UINT64_T,
                                MPI_SUM, MPI_COMM_WORLD),
                  "summing the points' counts");
    }

    void least(std::vector<double>& values) override {
        check(MPI_Allreduce(MPI_IN_PLACE, values.data(), as_count(values.size(), "the least figures"), MPI_DOUBLE, MPI_MIN,
                            MPI_COMM_WORLD),
              "agreeing on the points' box");
    }

    void give_check_points(int process, const snvr::Vec3& origin, const float* xyz, std::size_t floats) override {
        give_points(process, origin, xyz, floats);
    }

    void give_check(int process, const snvr::CheckShare& share) override {
        const std::int64_t sizes[7] = {std::int64_t(share.vertices.size()),     std::int64_t(share.triangles.size()),
                                       std::int64_t(share.measured.size()),     std::int64_t(share.range_groups.size()),
                                       std::int64_t(share.range_scaled.size()), std::int64_t(share.range_size),
                                       std::int64_t(share.point_groups.size())};
        const double figures[7] = {share.epsilon,         share.reach,           share.voxel,          share.points_frame[0],
                                   share.points_frame[1], share.points_frame[2], share.points_frame[3]};
        const auto put = [&](const void* data, std::size_t n, MPI_Datatype type) {
            check(MPI_Send(data, as_count(n, "a share of the check"), type, process, kCheckShare, MPI_COMM_WORLD),
                  "sending a share of the check");
        };
        put(sizes, 7, MPI_INT64_T);
        put(figures, 7, MPI_DOUBLE);
        put(share.vertices.data(), 3 * share.vertices.size(), MPI_DOUBLE);
        put(share.triangles.data(), 3 * share.triangles.size(), MPI_UINT32_T);
        put(share.measured.data(), share.measured.size(), MPI_UINT32_T);
        put(share.range_groups.data(), 2 * share.range_groups.size(), MPI_UINT32_T);
        put(share.range_scaled.data(), share.range_scaled.size(), MPI_DOUBLE);
        put(share.point_groups.data(), share.point_groups.size(), MPI_UINT32_T);
    }

    snvr::CheckShareFigures take_check(int process) override {
        snvr::CheckShareFigures got;
        std::int64_t sizes[3] = {0, 0, 0};
        double least = 0;
        const auto get = [&](void* data, std::size_t n, MPI_Datatype type) {
            check(MPI_Recv(data, as_count(n, "the check's figures"), type, process, kChecked, MPI_COMM_WORLD,
                           MPI_STATUS_IGNORE),
                  "receiving the check's figures");
        };
        get(sizes, 3, MPI_INT64_T);
        get(&least, 1, MPI_DOUBLE);
        got.points_inside = std::uint64_t(sizes[1]);
        got.depth_min = least;
        got.walls.resize(static_cast<std::size_t>(sizes[0]));
        got.unresolved.resize(static_cast<std::size_t>(sizes[2]));
        get(got.walls.data(), got.walls.size(), MPI_DOUBLE);
        get(got.unresolved.data(), got.unresolved.size(), MPI_UINT32_T);
        return got;
    }

    snvr::CheckShare check_share() override {
        snvr::CheckShare share;
        take_points_into(share.origin, share.points);
        std::int64_t sizes[7];
        double figures[7];
        const auto get = [&](void* data, std::size_t n, MPI_Datatype type) {
            check(MPI_Recv(data, as_count(n, "a share of the check"), type, 0, kCheckShare, MPI_COMM_WORLD,
                           MPI_STATUS_IGNORE),
                  "receiving a share of the check");
        };
        get(sizes, 7, MPI_INT64_T);
        get(figures, 7, MPI_DOUBLE);
        share.epsilon = figures[0];
        share.reach = figures[1];
        share.voxel = figures[2];
        std::copy(figures + 3, figures + 7, share.points_frame.begin());
        share.vertices.resize(static_cast<std::size_t>(sizes[0]));
        share.triangles.resize(static_cast<std::size_t>(sizes[1]));
        share.measured.resize(static_cast<std::size_t>(sizes[2]));
        share.range_groups.resize(static_cast<std::size_t>(sizes[3]));
        share.range_scaled.resize(static_cast<std::size_t>(sizes[4]));
        share.range_size = std::uint64_t(sizes[5]);
        share.point_groups.resize(static_cast<std::size_t>(sizes[6]));
        get(share.vertices.data(), 3 * share.vertices.size(), MPI_DOUBLE);
        get(share.triangles.data(), 3 * share.triangles.size(), MPI_UINT32_T);
        get(share.measured.data(), share.measured.size(), MPI_UINT32_T);
        get(share.range_groups.data(), 2 * share.range_groups.size(), MPI_UINT32_T);
        get(share.range_scaled.data(), share.range_scaled.size(), MPI_DOUBLE);
        get(share.point_groups.data(), share.point_groups.size(), MPI_UINT32_T);
        return share;
    }

    void send_check(const snvr::CheckShareFigures& figures) override {
        const std::int64_t sizes[3] = {std::int64_t(figures.walls.size()), std::int64_t(figures.points_inside),
                                       std::int64_t(figures.unresolved.size())};
        const auto put = [&](const void* data, std::size_t n, MPI_Datatype type) {
            check(MPI_Send(data, as_count(n, "the check's figures"), type, 0, kChecked, MPI_COMM_WORLD),
                  "sending the check's figures");
        };
        put(sizes, 3, MPI_INT64_T);
        put(&figures.depth_min, 1, MPI_DOUBLE);
        put(figures.walls.data(), figures.walls.size(), MPI_DOUBLE);
        put(figures.unresolved.data(), figures.unresolved.size(), MPI_UINT32_T);
    }

private:
    // Points from the root into a vector of this process's.
    void take_points_into(snvr::Vec3& origin, std::vector<float>& xyz) {
        take_points(origin, [&xyz](std::size_t floats) {
            xyz.resize(floats);
            return xyz.data();
        });
    }

    struct Outgoing {
        snvr::TileResult result;
        std::array<std::int64_t, kHeaderSize> header;
    };
    std::list<Outgoing> outgoing_;  // a list: what is sent from must not move
    std::vector<MPI_Request> requests_;
};

}  // namespace

// Open MPI on one machine, its messaging layer not chosen: the processes talk through
// shared memory (ob1's), and probing the networks' layers (cm's, ucx's) would take 0.2 s
// of the 0.37 s MPI's start and end cost two processes here.
void skip_network_probing() {
    const char* size = std::getenv("OMPI_COMM_WORLD_SIZE");
    const char* local = std::getenv("OMPI_COMM_WORLD_LOCAL_SIZE");
    if (!size || !local || std::string(size) != local || std::getenv("OMPI_MCA_pml")) return;
    ::setenv("OMPI_MCA_pml", "^cm,ucx", 0);
}

void start_processes(int& argc, char**& argv) {
    if (launched_size() < 2) return;  // alone: one process, no MPI
    skip_network_probing();
    int provided = 0;
    // Only the main thread calls MPI; OpenMP's threads never do.
    check(MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided), "starting");
    started = true;
}

void end_processes(bool failed) {
    if (!started) return;
    // A failure on one process would leave the others waiting for its tiles.
    if (failed && process_count() > 1) MPI_Abort(MPI_COMM_WORLD, 1);
    MPI_Finalize();
    started = false;
}

int process_count() {
    int n = 1;
    if (started) MPI_Comm_size(MPI_COMM_WORLD, &n);
    return n;
}

int process_rank() {
    int r = 0;
    if (started) MPI_Comm_rank(MPI_COMM_WORLD, &r);
    return r;
}

std::shared_ptr<snvr::TileScheduler> process_tiles() {
    if (process_count() < 2) return nullptr;
    return std::make_shared<MpiTiles>();
}

}  // namespace cli
