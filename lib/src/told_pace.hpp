// How far a long loop has come, said between its parts (the caller's thread: a cancel
// thrown from the progress callback then stops it): at most every few seconds, with the
// time left reckoned from its pace so far.
#pragma once
#include <cmath>
#include <cstddef>

#include "snvr/stopwatch.hpp"

namespace snvr::detail {

class ToldPace {
public:
    // Seconds between two messages, at the least.
    static constexpr double kEverySeconds = 2;

    // Called at each part's end with `done` of `all` (0: the loop starts, its pace afresh):
    // whether to say so now, and then the seconds left in `left`.
    bool due(std::size_t done, std::size_t all, double& left) {
        const double lap = clock_.lap();
        seconds_ = done == 0 ? 0 : seconds_ + lap;
        quiet_ += lap;
        if (done == 0 || done >= all || quiet_ < kEverySeconds) return false;
        quiet_ = 0;
        left = std::ceil(seconds_ / double(done) * double(all - done));
        return true;
    }

private:
    Stopwatch clock_;
    double seconds_ = 0, quiet_ = 0;
};

}  // namespace snvr::detail
