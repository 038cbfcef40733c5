#include "isolated.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <exception>

namespace snvr::bench {

namespace {

void write_all(int fd, const std::string& s) {
    std::size_t done = 0;
    while (done < s.size()) {
        const ssize_t n = ::write(fd, s.data() + done, s.size() - done);
        if (n <= 0) return;
        done += std::size_t(n);
    }
}

}  // namespace

std::vector<Record> run_isolated(const std::function<std::vector<Record>()>& measure) {
    std::fflush(nullptr);
    int fds[2];
    if (::pipe(fds) != 0) return {Record().set("error", "pipe() failed")};
    const pid_t pid = ::fork();
    if (pid < 0) return {Record().set("error", "fork() failed")};
    if (pid == 0) {
        ::close(fds[0]);
        std::string out;
        try {
            for (const Record& r : measure()) out += r.serialize() + "\x1e\n";  // record separator
        } catch (const std::exception& e) {
            out = Record().set("error", e.what()).serialize() + "\x1e\n";
        }
        write_all(fds[1], out);
        ::close(fds[1]);
        std::fflush(nullptr);
        ::_exit(0);
    }
    ::close(fds[1]);
    std::string text;
    char buf[4096];
    ssize_t n;
    while ((n = ::read(fds[0], buf, sizeof buf)) > 0) text.append(buf, std::size_t(n));
    ::close(fds[0]);
    int status = 0;
    ::waitpid(pid, &status, 0);
    std::vector<Record> records;
    std::size_t start = 0, end;
    while ((end = text.find("\x1e\n", start)) != std::string::npos) {
        records.push_back(Record::deserialize(text.substr(start, end - start)));
        start = end + 2;
    }
    if (records.empty())
        records.push_back(Record().set("error", WIFSIGNALED(status) ? "the measurement died with signal " + std::to_string(WTERMSIG(status))
                                                                     : std::string("the measurement returned nothing")));
    return records;
}

}  // namespace snvr::bench
