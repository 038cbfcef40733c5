// make_report (report.hpp): the run's figures gathered once, for every view of them;
// the number formats the views and snvr-cl share.
#include "snvr/report.hpp"

#include <sys/resource.h>

#include <algorithm>
#include <cstdarg>
#include <cstdio>

namespace snvr {

CycleTotals cycle_totals(const std::vector<StepStats>& steps) {
    CycleTotals c;
    for (const StepStats& s : steps) {
        c.total += s.cycles;
        c.most_in_a_step = std::max(c.most_in_a_step, s.cycles);
        c.not_converged += s.converged ? 0 : 1;
    }
    return c;
}

std::size_t peak_rss_bytes() {
    rusage usage{};
    if (getrusage(RUSAGE_SELF, &usage) != 0) return 0;
#if defined(__APPLE__)
    return std::size_t(usage.ru_maxrss);  // bytes on macOS
#else
    return std::size_t(usage.ru_maxrss) * 1024;  // KiB on Linux and the BSDs
#endif
}

std::size_t huge_page_bytes() {
    std::FILE* f = std::fopen("/proc/self/smaps_rollup", "r");
    if (!f) return 0;
    char line[256];
    unsigned long long kib = 0;
    while (std::fgets(line, sizeof line, f))
        if (std::sscanf(line, "AnonHugePages: %llu kB", &kib) == 1) break;
    std::fclose(f);
    return std::size_t(kib) * 1024;
}

std::string format_text(const char* format, ...) {
    va_list args;
    va_start(args, format);
    va_list again;
    va_copy(again, args);
    const int n = std::vsnprintf(nullptr, 0, format, args);
    va_end(args);
    std::string out(n > 0 ? std::size_t(n) : 0, '\0');
    if (n > 0) std::vsnprintf(out.data(), out.size() + 1, format, again);
    va_end(again);
    return out;
}

std::string grouped(std::size_t n) {
    std::string digits = std::to_string(n), out;
    for (std::size_t i = 0; i < digits.size(); ++i) {
        if (i > 0 && (digits.size() - i) % 3 == 0) out += ',';
        out += digits[i];
    }
    return out;
}

RunReport make_report(const Shell& shell, const RunFiles& files) {
    const double total = files.total_seconds > 0 ? files.total_seconds
                                                 : files.read_seconds + shell.seconds.total + files.write_seconds;
    return RunReport{shell, files, cycle_totals(shell.run.steps), peak_rss_bytes(), huge_page_bytes(), total};
}

}  // namespace snvr
