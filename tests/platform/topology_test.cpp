// Topology: plausible counts, a machine line naming the CPU and the ISAs, pinning.
#include <thread>

#include <gtest/gtest.h>

#include "simdbvh/kernels/isa.h"
#include "simdbvh/platform/topology.h"

namespace simdbvh {
namespace {

TEST(Topology, PlausibleCounts) {
    const Topology& t = topology();
    EXPECT_GE(t.logical_cpus, 1);
    if (t.physical_cores > 0) {
        EXPECT_LE(t.physical_cores, t.logical_cpus);
    }
    if (t.from_hwloc) {
        EXPECT_GT(t.physical_cores, 0);
    }
    if (t.l1d_bytes && t.l2_bytes) {
        EXPECT_LE(t.l1d_bytes, t.l2_bytes);
    }
    std::cout << machine_line() << "\n";
}

TEST(Topology, MachineLineNamesCpuAndIsas) {
    const std::string line = machine_line();
    EXPECT_NE(line.find(std::string(cpu_name())), std::string::npos);
    for (Isa isa : supported_isas()) EXPECT_NE(line.find(std::string(name(isa))), std::string::npos) << line;
    EXPECT_NE(line.find("active"), std::string::npos);
}

TEST(Topology, PinToCore) {
    EXPECT_FALSE(pin_current_thread_to_core(-1));
    EXPECT_FALSE(pin_current_thread_to_core(1 << 20));
    if (!topology().from_hwloc) GTEST_SKIP() << "built without hwloc: pinning unavailable";
    bool ok = false;
    std::thread th([&] { ok = pin_current_thread_to_core(0); });  // a fresh thread: the test's own stays free
    th.join();
    EXPECT_TRUE(ok);
}

}  // namespace
}  // namespace simdbvh
