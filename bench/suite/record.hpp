// One benchmark result: ordered named values (numbers or text), written as a JSON line
// and passed from the measuring child process to the parent as tab-separated lines.
#pragma once
#include <string>
#include <utility>
#include <vector>

namespace snvr::bench {

class Record {
public:
    Record& set(const std::string& key, double value);
    Record& set(const std::string& key, const std::string& value);
    Record& set(const std::string& key, const char* value) { return set(key, std::string(value)); }

    bool has(const std::string& key) const;
    double number(const std::string& key) const;  // NaN when absent or text
    std::string text(const std::string& key) const;  // "" when absent; numbers formatted

    std::string json() const;
    std::string serialize() const;                    // one "key\tn|t\tvalue" line per field
    static Record deserialize(const std::string& lines);

private:
    struct Field {
        std::string key;
        bool is_text;
        double number;
        std::string text;
    };
    const Field* find(const std::string& key) const;
    std::vector<Field> fields_;
};

// A number for the tables: printf's format f, "-" when not finite.
std::string fmt(const char* f, double v);

}  // namespace snvr::bench
