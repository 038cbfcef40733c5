// snvr-cl devices and snvr-cl sample.
#include "commands.hpp"

#include <algorithm>
#include <iostream>

#include "options.hpp"
#include "report.hpp"
#include "snvr/devices.hpp"
#include "snvr/point_io.hpp"
#include "snvr/error.hpp"
#include "snvr/shapes.hpp"

namespace cli {
namespace {

std::string memory_text(std::size_t bytes) {
    if (bytes == 0) return "-";
    const double gib = double(bytes) / (1024.0 * 1024.0 * 1024.0);
    return gib >= 1 ? snvr::format_text("%.1f GiB", gib) : snvr::format_text("%.0f MiB", double(bytes) / (1024.0 * 1024.0));
}

void print_table(std::ostream& out, const std::vector<std::vector<std::string>>& rows) {
    std::vector<std::size_t> width;
    for (const auto& row : rows)
        for (std::size_t c = 0; c < row.size(); ++c) {
            width.resize(std::max(width.size(), row.size()));
            width[c] = std::max(width[c], row[c].size());
        }
    for (const auto& row : rows) {
        std::string line;
        for (std::size_t c = 0; c < row.size(); ++c)
            line += row[c] + (c + 1 < row.size() ? std::string(width[c] - row[c].size() + 2, ' ') : "");
        out << line << '\n';
    }
}

}  // namespace

int run_devices(const std::vector<std::string>& args) {
    if (!parse_devices(args, std::cout)) return 0;
    const std::vector<snvr::DeviceInfo> devices = snvr::list_devices();
    if (devices.empty()) {
        std::cout << "no devices found\n";
        return 0;
    }
    std::vector<std::vector<std::string>> rows{{"ID", "KIND", "NAME", "UNITS", "MEMORY", "FP64", "AVAILABLE"}};
    for (const snvr::DeviceInfo& d : devices)
        rows.push_back({d.id, d.kind, d.name, std::to_string(d.compute_units), memory_text(d.memory_bytes),
                        d.fp64 ? "yes" : "no",
                        std::string(d.available ? "yes" : "no") + (d.note.empty() ? "" : " (" + d.note + ")")});
    print_table(std::cout, rows);
    return 0;
}

int run_sample(const std::vector<std::string>& args) {
    const std::optional<SampleOptions> parsed = parse_sample(args, std::cout);
    if (!parsed) return 0;
    if (parsed->shape == "city") {  // made as it is written
        snvr::write_point_stream(
            parsed->output, parsed->points,
            snvr::format_text("snvr-cl sample city --points %zu --seed %llu (metres)", parsed->points,
                              (unsigned long long)parsed->seed),
            [&](const std::function<void(const snvr::PointSet&)>& emit) { snvr::shapes::city_scan(parsed->points, parsed->seed, emit); });
        std::cerr << "wrote " << grouped(parsed->points) << " points to " << snvr::printable(parsed->output) << '\n';
        return 0;
    }
    snvr::PointSet points;
    try {
        const snvr::PointSet surface = parsed->random ? snvr::shapes::random_by_name(parsed->shape, parsed->random, parsed->seed)
                                                      : snvr::shapes::by_name(parsed->shape, parsed->spacing);
        points = snvr::shapes::with_outliers(surface, parsed->outliers);
    } catch (const snvr::ParameterError& e) {
        throw UsageError(e.what());  // an unknown shape name or a bad spacing came from the command line
    }
    const std::string drawn = parsed->random ? snvr::format_text("--random %zu --seed %llu", parsed->random,
                                                                 (unsigned long long)parsed->seed)
                                             : snvr::format_text("--spacing %g", parsed->spacing);
    snvr::write_points(points, parsed->output, snvr::format_text("snvr-cl sample %s %s --outliers %g", parsed->shape.c_str(),
                                                                 drawn.c_str(), parsed->outliers));
    std::cerr << "wrote " << grouped(points.size()) << " points to " << snvr::printable(parsed->output) << '\n';
    return 0;
}

}  // namespace cli
