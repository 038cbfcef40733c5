#include "record.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

namespace snvr::bench {

namespace {

std::string json_string(const std::string& s) {
    std::string out = "\"";
    for (char c : s) {
        if (c == '"' || c == '\\') out += '\\', out += c;
        else if (c == '\n') out += "\\n";
        else if (c == '\t') out += "\\t";
        else if (static_cast<unsigned char>(c) < 0x20) out += ' ';
        else out += c;
    }
    return out + "\"";
}

std::string format_number(double v) {
    if (!std::isfinite(v)) return "null";
    char buf[32];
    // Counts (points, cells, triangles) in full; other figures to six digits.
    std::snprintf(buf, sizeof buf, v == std::floor(v) && std::abs(v) < 1e15 ? "%.0f" : "%.6g", v);
    return buf;
}

}  // namespace

Record& Record::set(const std::string& key, double value) {
    fields_.push_back({key, false, value, {}});
    return *this;
}

Record& Record::set(const std::string& key, const std::string& value) {
    fields_.push_back({key, true, 0, value});
    return *this;
}

const Record::Field* Record::find(const std::string& key) const {
    for (auto it = fields_.rbegin(); it != fields_.rend(); ++it)
        if (it->key == key) return &*it;
    return nullptr;
}

bool Record::has(const std::string& key) const { return find(key) != nullptr; }

double Record::number(const std::string& key) const {
    const Field* f = find(key);
    return f && !f->is_text ? f->number : std::nan("");
}

std::string Record::text(const std::string& key) const {
    const Field* f = find(key);
    if (!f) return "";
    return f->is_text ? f->text : format_number(f->number);
}

std::string Record::json() const {
    std::string out = "{";
    for (std::size_t i = 0; i < fields_.size(); ++i) {
        if (i) out += ", ";
        out += json_string(fields_[i].key) + ": " + (fields_[i].is_text ? json_string(fields_[i].text) : format_number(fields_[i].number));
    }
    return out + "}";
}

std::string Record::serialize() const {
    std::string out;
    char buf[40];
    for (const Field& f : fields_) {
        std::snprintf(buf, sizeof buf, "%.17g", f.number);
        std::string value = f.is_text ? f.text : buf;
        for (char& c : value)
            if (c == '\n' || c == '\t') c = ' ';
        out += f.key + '\t' + (f.is_text ? 't' : 'n') + '\t' + value + '\n';
    }
    return out;
}

Record Record::deserialize(const std::string& lines) {
    Record r;
    std::istringstream in(lines);
    std::string line;
    while (std::getline(in, line)) {
        const std::size_t a = line.find('\t'), b = a == std::string::npos ? a : line.find('\t', a + 1);
        if (b == std::string::npos) continue;
        const std::string key = line.substr(0, a), value = line.substr(b + 1);
        if (line[a + 1] == 't') r.set(key, value);
        else r.set(key, std::strtod(value.c_str(), nullptr));
    }
    return r;
}

std::string fmt(const char* f, double v) {
    if (!std::isfinite(v)) return "-";
    char buf[64];
    std::snprintf(buf, sizeof buf, f, v);
    return buf;
}

}  // namespace snvr::bench
