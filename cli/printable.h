#pragma once
// What the CLI prints is text for a terminal: control characters in it (a file
// name can hold any byte: ESC sequences, BEL, CR) are shown escaped, never sent.
#include <string>
#include <string_view>

namespace simdbvh::cli {

// `s` with C0 controls other than newline and tab, DEL, and the C1 controls (U+0080..U+009F, UTF-8 C2 80..9F)
// escaped as \xNN and \u00NN; every other byte (UTF-8 text included) as it is.
std::string printable(std::string_view s);

// Sends everything written to std::cout and std::cerr through printable(), byte by byte as it is written
// (the order against printf is kept). Once, at the start of main.
void escape_terminal_output();

}  // namespace simdbvh::cli
