#pragma once
// The library's one exception type: it never prints and never exits.
#include <stdexcept>
#include <string>

namespace simdbvh {

class Error : public std::runtime_error {
public:
    explicit Error(const std::string& what) : std::runtime_error(what) {}
};

}  // namespace simdbvh
