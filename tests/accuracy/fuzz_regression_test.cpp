// Inputs found by the fuzzers (scripts/fuzz.sh) and kept under tests/data/fuzz:
// <target>-<name>.<ext>. Loading each must give a mesh or a clean
// simdbvh::Error naming the file, never a crash (run under ASan in the asan preset).
#include <gtest/gtest.h>

#include <filesystem>

#include "simdbvh/kernels/error.h"
#include "simdbvh/io/load.h"
#include "simdbvh/io/ray_files.h"
#include "support/scene.h"

namespace fs = std::filesystem;

TEST(FuzzRegressions, EveryKeptInputLoadsOrThrowsACleanError) {
    const fs::path dir = test::data_file("fuzz");
    std::size_t n = 0;
    for (const auto& e : fs::directory_iterator(dir)) {
        if (!e.is_regular_file() || e.path().extension() == ".md") continue;
        ++n;
        SCOPED_TRACE(e.path().string());
        const std::string fname = e.path().filename().string();
        const bool rays = fname.rfind("fuzz_read_rays", 0) == 0 || fname.rfind("read_rays", 0) == 0;
        try {
            if (rays) (void)simdbvh::io::read_rays(e.path());
            else (void)simdbvh::io::load_mesh(e.path());
        } catch (const simdbvh::Error& err) {
            EXPECT_NE(std::string(err.what()).find(e.path().filename().string()), std::string::npos) << err.what();
        }
    }
    if (n == 0) GTEST_SKIP() << "no fuzzer findings kept in " << dir;
}
