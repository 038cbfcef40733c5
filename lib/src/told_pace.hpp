// How far a long loop has come, said between its parts (the caller's thread: a cancel
// thrown from the progress callback then stops it): at most every few seconds, with the
// time left reckoned from its pace so far.
#pragma once
#include <cmath>
#include <cstddef>
#include <functional>
#include <string>

#include "snvr/stopwatch.hpp"

namespace snvr::detail {

// How far a loop has come: told(done, all) from the caller's thread, 0 first and all
// last; what it throws stops the loop and is thrown on.
using Told = std::function<void(std::size_t done, std::size_t all)>;
// Which part of a stage begins (a few words), from the caller's thread; what it throws
// stops the stage and is thrown on.
using Begun = std::function<void(const std::string& part)>;

// part(begin, end) over [0, count) in pieces run one after another (one piece without
// `told`), told between them: a loop whose pieces' items the threads share.
constexpr std::size_t kToldPieces = 16;
template <class Part>
void in_told_pieces(std::size_t count, const Told& told, const Part& part) {
    const std::size_t pieces = told ? kToldPieces : 1;
    if (told) told(0, count);
    for (std::size_t r = 0; r < pieces; ++r) {
        const std::size_t end = count * (r + 1) / pieces;
        part(count * r / pieces, end);
        if (told) told(end, count);
    }
}

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
