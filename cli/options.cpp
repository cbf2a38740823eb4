#include "options.h"

#include <charconv>
#include <cmath>
#include <cstdlib>
#include <string_view>

namespace simdbvh::cli {

Options::Options(const std::string& command, const std::vector<std::string>& args, const std::set<std::string>& valued,
                 const std::set<std::string>& flags)
    : command_(command) {
    for (std::size_t i = 0; i < args.size(); ++i) {
        std::string a = args[i];
        if (a.rfind("--", 0) != 0) throw UsageError("'" + command + "': unexpected argument '" + a + "'");
        std::string key = a.substr(2), value;
        bool inline_value = false;
        if (auto eq = key.find('='); eq != std::string::npos) {
            value = key.substr(eq + 1);
            key = key.substr(0, eq);
            inline_value = true;
        }
        if (flags.count(key)) {
            if (inline_value) throw UsageError("'" + command + "': option --" + key + " takes no value");
            flags_.insert(key);
        } else if (valued.count(key)) {
            if (!inline_value) {
                if (i + 1 >= args.size()) throw UsageError("'" + command + "': option --" + key + " needs a value");
                value = args[++i];
            }
            values_[key] = value;
        } else {
            throw UsageError("'" + command + "': unknown option --" + key);
        }
    }
}

std::string Options::get(const std::string& key, const std::string& fallback) const {
    auto it = values_.find(key);
    return it == values_.end() ? fallback : it->second;
}

std::string Options::require(const std::string& key) const {
    auto it = values_.find(key);
    if (it == values_.end()) throw UsageError("'" + command_ + "': missing --" + key);
    return it->second;
}

long long Options::get_int(const std::string& key, long long fallback, long long lo, long long hi) const {
    auto it = values_.find(key);
    if (it == values_.end()) return fallback;
    long long v = 0;
    const std::string& s = it->second;
    auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (ec != std::errc() || p != s.data() + s.size() || v < lo || v > hi)
        throw UsageError("'" + command_ + "': --" + key + " must be an integer in " + std::to_string(lo) + ".." +
                         std::to_string(hi) + ", got '" + s + "'");
    return v;
}

std::optional<float> Options::get_float(const std::string& key) const {
    auto it = values_.find(key);
    if (it == values_.end()) return std::nullopt;
    std::string_view s = it->second;
    const bool plus = !s.empty() && s[0] == '+';
    if (plus) s.remove_prefix(1);
    if (s.empty() || (plus && (s[0] == '+' || s[0] == '-'))) return std::nullopt;
    float v = 0;
    auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v, std::chars_format::general);
    if (p != s.data() + s.size()) return std::nullopt;
    if (ec == std::errc::result_out_of_range) {
        // from_chars reports underflow too: strtof gives the correctly rounded subnormal (or zero); overflow
        // (an infinite result from a finite literal) is out of range.
        v = std::strtof(std::string(s).c_str(), nullptr);
        if (std::isinf(v)) return std::nullopt;
    } else if (ec != std::errc()) {
        return std::nullopt;
    }
    return v;
}

}  // namespace simdbvh::cli
