#pragma once
// Strict command-line options: every command declares what it accepts; an
// unknown option or a missing value is an error, never ignored.
#include <map>
#include <optional>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

namespace simdbvh::cli {

struct UsageError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

class Options {
public:
    // valued: options taking a value (--scene S); flags: options without one.
    Options(const std::string& command, const std::vector<std::string>& args, const std::set<std::string>& valued,
            const std::set<std::string>& flags);
    bool has(const std::string& key) const { return values_.count(key) || flags_.count(key); }
    std::string get(const std::string& key, const std::string& fallback = "") const;
    std::string require(const std::string& key) const;
    long long get_int(const std::string& key, long long fallback, long long lo, long long hi) const;
    // A float, strictly: the whole value is one number (std::from_chars: no spaces, an optional leading '+';
    // inf, infinity and nan are numbers), correctly rounded, a subnormal included; one beyond the float range
    // is refused. The caller checks the range.
    std::optional<float> get_float(const std::string& key) const;

private:
    std::string command_;
    std::map<std::string, std::string> values_;
    std::set<std::string> flags_;
};

}  // namespace simdbvh::cli
