#pragma once
// The library's one exception type: it never prints and never exits.
// Messages name the item and the problem, with no program prefix (the CLI
// adds "simdbvh: ").
#include <cstddef>
#include <stdexcept>
#include <string>

namespace simdbvh {

class Error : public std::runtime_error {
public:
    explicit Error(const std::string& what) : std::runtime_error(what) {}
};

namespace detail {
// The one check of an output (or input) span against what a call needs:
// throws "<what> holds <got> elements, needs <want>" when got < want.
inline void check_size(std::size_t got, std::size_t want, const char* what) {
    if (got < want)
        throw Error(std::string(what) + " holds " + std::to_string(got) + " elements, needs " + std::to_string(want));
}
}  // namespace detail

}  // namespace simdbvh
