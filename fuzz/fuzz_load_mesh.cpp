// libFuzzer target: io::load_mesh on every format, plain and gzip.
// Input: byte 0 selects the case, the rest is the file.
//   bits 0-1: extension .ply .obj .stl .off
//   bits 2-3: 0 plain; 1 gzip-compress the rest (fuzzes the parsers behind
//             zlib); 2 the rest as a raw .gz file (fuzzes the gzip handling)
//   bit 4:    LoadOptions::drop_invalid
// Allowed outcome: a mesh that validate() accepts, or simdbvh::Error. Any other
// exception, a crash or a sanitizer report is a finding.
#include <zlib.h>

#include <string>
#include <vector>

#include "fuzz_util.h"
#include "simdbvh/kernels/error.h"
#include "simdbvh/io/load.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size < 1) return 0;
    const unsigned sel = data[0];
    static const char* kExt[4] = {".ply", ".obj", ".stl", ".off"};
    std::string name = std::string("in") + kExt[sel & 3];
    const std::uint8_t* body = data + 1;
    std::size_t n = size - 1;
    std::vector<unsigned char> packed;
    const unsigned mode = (sel >> 2) & 3;
    if (mode == 1) {  // gzip stream of the body (deflateInit2 with 16 + MAX_WBITS: gzip header)
        z_stream zs{};
        if (deflateInit2(&zs, 1, Z_DEFLATED, 16 + MAX_WBITS, 8, Z_DEFAULT_STRATEGY) != Z_OK) return 0;
        packed.resize(deflateBound(&zs, uLong(n)) + 64);
        zs.next_in = const_cast<Bytef*>(body);
        zs.avail_in = uInt(n);
        zs.next_out = packed.data();
        zs.avail_out = uInt(packed.size());
        deflate(&zs, Z_FINISH);
        packed.resize(zs.total_out);
        deflateEnd(&zs);
        body = packed.data();
        n = packed.size();
    }
    if (mode != 0) name += ".gz";
    const auto path = simdbvh::fuzz::write_input(name, body, n);
    simdbvh::io::LoadOptions opts;
    opts.drop_invalid = (sel >> 4) & 1;
    try {
        simdbvh::io::LoadReport report;
        const simdbvh::Mesh m = simdbvh::io::load_mesh(path, opts, &report);
        simdbvh::validate(m);  // what the loader returns must be a valid mesh
    } catch (const simdbvh::Error&) {}
    return 0;
}
