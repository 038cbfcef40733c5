#include "report.hpp"
#include "snvr/error.hpp"

#include <iostream>

namespace cli {

void warn(const std::string& message) { std::cerr << "snvr-cl: warning: " << snvr::printable(message) << std::endl; }

bool ProgressPace::due(const snvr::Progress& p) {
    quiet_ += clock_.lap();
    const bool paced = !p.outcome && !p.message.empty() && p.stage != "step" && p.stage != "tile";
    if (paced && p.stage == stage_ && quiet_ < kEverySeconds) return false;
    stage_ = p.stage;
    quiet_ = 0;
    return true;
}

void print_progress(std::ostream& out, const snvr::Progress& p) {
    if (p.stage == "step" && p.stats) {
        const snvr::StepStats& s = *p.stats;
        out << snvr::format_text("step %d/%d: %d V-cycle%s, residual %.2g, %.2f s%s", p.step, p.steps, s.cycles,
                   s.cycles == 1 ? "" : "s", s.residual, s.seconds_linear + s.seconds_nonlinear,
                   s.converged ? "" : " (not converged)");
    } else if (p.stage == "step") {
        out << snvr::format_text("step %d/%d", p.step, p.steps);
    } else {
        out << p.stage << (p.message.empty() ? "..." : ": " + snvr::printable(p.message));
    }
    if (p.stage == "step" && !p.message.empty()) out << ": " << p.message;
    out << std::endl;  // flushed: progress must show while the run goes on
}

}  // namespace cli
