// Processes as threads of one process (tests): bytes in order between two of them, and
// sums and least values over all, what the points' shared filing and the check of a mesh
// in slabs ask of a run's processes. Nothing else is asked.
#pragma once
#include <array>
#include <condition_variable>
#include <cstdint>
#include <cstring>
#include <deque>
#include <exception>
#include <functional>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <thread>
#include <vector>

#include "snvr/tiles.hpp"

namespace snvr::testing {

class ThreadProcesses {
public:
    explicit ThreadProcesses(int n) : n_(n), boxes_(std::size_t(n * n)) {}
    class One : public TileScheduler {
    public:
        One(ThreadProcesses& all, int rank) : all_(all), rank_(rank) {}
        int processes() const override { return all_.n_; }
        int rank() const override { return rank_; }
        void send_bytes(int to, const void* bytes, std::size_t size) override {
            std::vector<char> copy(size);
            if (size) std::memcpy(copy.data(), bytes, size);
            std::lock_guard<std::mutex> lock(all_.mutex_);
            all_.box(rank_, to).push_back(std::move(copy));
            all_.changed_.notify_all();
        }
        void receive_bytes(int from, const std::function<void*(std::size_t)>& room) override {
            std::vector<char> got;
            {
                std::unique_lock<std::mutex> lock(all_.mutex_);
                all_.changed_.wait(lock, [&] { return !all_.box(from, rank_).empty(); });
                got = std::move(all_.box(from, rank_).front());
                all_.box(from, rank_).pop_front();
            }
            void* to = room(got.size());
            if (!got.empty()) std::memcpy(to, got.data(), got.size());
        }
        void sum(std::vector<std::uint64_t>& values) override {
            all_.reduce(values, all_.total_, [](std::uint64_t x, std::uint64_t y) { return x + y; });
        }
        void least(std::vector<double>& values) override {
            all_.reduce(values, all_.smallest_, [](double x, double y) { return std::min(x, y); });
        }
        // Not asked of them.
        void send(TileResult) override { refuse(); }
        void sent() override { refuse(); }
        bool waiting() override { refuse(); }
        TileResult receive() override { refuse(); }
        std::vector<int> most(const std::vector<int>&) override { refuse(); }
        void give_upsampling(int, const UpsampleShare&) override { refuse(); }
        std::vector<double> take_upsampled(int) override { refuse(); }
        UpsampleShare upsampling() override { refuse(); }
        void send_upsampled(const std::vector<double>&) override { refuse(); }
        void share(std::vector<double>&, std::vector<int>&) override { refuse(); }
        void give_points(int, const Vec3&, const float*, std::size_t) override { refuse(); }
        void take_points(Vec3&, const std::function<float*(std::size_t)>&) override { refuse(); }
        void give_check_points(int, const Vec3&, const float*, std::size_t) override { refuse(); }
        void give_check(int, const CheckShare&) override { refuse(); }
        CheckShareFigures take_check(int) override { refuse(); }
        CheckShare check_share() override { refuse(); }
        void send_check(const CheckShareFigures&) override { refuse(); }

    private:
        [[noreturn]] static void refuse() { throw std::logic_error("not asked of processes as threads"); }
        ThreadProcesses& all_;
        int rank_;
    };

private:
    std::deque<std::vector<char>>& box(int from, int to) { return boxes_[std::size_t(from * n_ + to)]; }
    // Every process's values combined by op, once all have come, into each one's. Rounds
    // take turns with two pools: a process slow to copy one round's result reads it
    // while the next round fills the other.
    template <class T, class Op>
    void reduce(std::vector<T>& values, std::array<std::vector<T>, 2>& pools, Op op) {
        std::unique_lock<std::mutex> lock(mutex_);
        const std::size_t round = round_;
        std::vector<T>& pool = pools[round % 2];
        if (arrived_ == 0) pool = values;
        else
            for (std::size_t i = 0; i < values.size(); ++i) pool[i] = op(pool[i], values[i]);
        if (++arrived_ == n_) {
            arrived_ = 0;
            ++round_;
            changed_.notify_all();
        } else {
            changed_.wait(lock, [&] { return round_ != round; });
        }
        values = pool;
    }
    int n_;
    std::vector<std::deque<std::vector<char>>> boxes_;
    std::mutex mutex_;
    std::condition_variable changed_;
    std::array<std::vector<std::uint64_t>, 2> total_;
    std::array<std::vector<double>, 2> smallest_;
    int arrived_ = 0;
    std::size_t round_ = 0;
};

// Each process of `all`, the first at [0].
inline std::vector<std::unique_ptr<ThreadProcesses::One>> each_of(ThreadProcesses& all, int processes) {
    std::vector<std::unique_ptr<ThreadProcesses::One>> each;
    for (int p = 0; p < processes; ++p) each.push_back(std::make_unique<ThreadProcesses::One>(all, p));
    return each;
}


// `work(process)` on each of `processes` processes as threads, the first on this one.
inline void on_threads(int processes, const std::function<void(TileScheduler&)>& work) {
    ThreadProcesses all(processes);
    const auto each = each_of(all, processes);
    std::vector<std::thread> others;
    std::vector<std::exception_ptr> failed(static_cast<std::size_t>(processes));
    for (int p = 1; p < processes; ++p)
        others.emplace_back([&, p] {
            try {
                work(*each[std::size_t(p)]);
            } catch (...) {
                failed[std::size_t(p)] = std::current_exception();
            }
        });
    try {
        work(*each[0]);
    } catch (...) {
        failed[0] = std::current_exception();
    }
    for (std::thread& o : others) o.join();
    for (const auto& f : failed)
        if (f) std::rethrow_exception(f);
}

}  // namespace snvr::testing
