#include "printable.h"

#include <iostream>
#include <streambuf>

namespace simdbvh::cli {

namespace {

constexpr char kHex[] = "0123456789abcdef";

bool is_control(unsigned char c) { return (c < 0x20 && c != '\n' && c != '\t') || c == 0x7f; }

// The stream filter: each byte forwarded at once, a lone 0xC2 held until the next byte says whether it
// starts a C1 control.
class EscapingBuf final : public std::streambuf {
public:
    explicit EscapingBuf(std::streambuf* out) : out_(out) {}

protected:
    int_type overflow(int_type ch) override {
        if (traits_type::eq_int_type(ch, traits_type::eof())) return sync() == 0 ? traits_type::not_eof(ch) : ch;
        return put(static_cast<unsigned char>(traits_type::to_char_type(ch))) ? ch : traits_type::eof();
    }
    std::streamsize xsputn(const char* s, std::streamsize n) override {
        for (std::streamsize i = 0; i < n; ++i)
            if (!put(static_cast<unsigned char>(s[i]))) return i;
        return n;
    }
    int sync() override {
        if (held_) {
            held_ = false;
            if (!raw(0xc2)) return -1;
        }
        return out_->pubsync();
    }

private:
    bool raw(unsigned char c) { return !traits_type::eq_int_type(out_->sputc(char(c)), traits_type::eof()); }
    bool escaped(const char* prefix, unsigned char c) {
        for (const char* p = prefix; *p; ++p)
            if (!raw(static_cast<unsigned char>(*p))) return false;
        return raw(static_cast<unsigned char>(kHex[c >> 4])) && raw(static_cast<unsigned char>(kHex[c & 15]));
    }
    bool put(unsigned char c) {
        if (held_) {
            held_ = false;
            if (c >= 0x80 && c <= 0x9f) return escaped("\\u00", c);
            if (!raw(0xc2)) return false;
        }
        if (c == 0xc2) {
            held_ = true;
            return true;
        }
        return is_control(c) ? escaped("\\x", c) : raw(c);
    }

    std::streambuf* out_;
    bool held_ = false;
};

}  // namespace

std::string printable(std::string_view s) {
    std::string out;
    for (std::size_t i = 0; i < s.size(); ++i) {
        const auto c = static_cast<unsigned char>(s[i]);
        const auto next = i + 1 < s.size() ? static_cast<unsigned char>(s[i + 1]) : 0;
        if (c == 0xc2 && next >= 0x80 && next <= 0x9f) {
            out += "\\u00";
            out += kHex[next >> 4];
            out += kHex[next & 15];
            ++i;
        } else if (is_control(c)) {
            out += "\\x";
            out += kHex[c >> 4];
            out += kHex[c & 15];
        } else {
            out += char(c);
        }
    }
    return out;
}

void escape_terminal_output() {
    // Never destroyed: the streams are flushed at exit, after every static object of ours is gone.
    static EscapingBuf* out = new EscapingBuf(std::cout.rdbuf());
    static EscapingBuf* err = new EscapingBuf(std::cerr.rdbuf());
    std::cout.rdbuf(out);
    std::cerr.rdbuf(err);
}

}  // namespace simdbvh::cli
