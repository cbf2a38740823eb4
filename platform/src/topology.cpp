// Machine topology via hwloc (SIMDBVH_HAVE_HWLOC) or the C++/POSIX fallbacks.
#include "simdbvh/platform/topology.h"

#include <string>
#include <thread>

#include "simdbvh/platform/internal/platform.h"
#include "simdbvh/kernels/isa.h"

#if defined(SIMDBVH_HAVE_HWLOC)
#include <hwloc.h>
#endif

namespace simdbvh {
namespace {

#if defined(SIMDBVH_HAVE_HWLOC)
// Loaded once and kept for the process lifetime (read-only afterwards, which
// hwloc allows from several threads).
hwloc_topology_t hwloc_topo() {
    static hwloc_topology_t topo = [] {
        hwloc_topology_t t = nullptr;
        if (hwloc_topology_init(&t) != 0) return hwloc_topology_t(nullptr);
        if (hwloc_topology_load(t) != 0) {
            hwloc_topology_destroy(t);
            return hwloc_topology_t(nullptr);
        }
        return t;
    }();
    return topo;
}

std::size_t cache_size(hwloc_topology_t t, hwloc_obj_type_t type) {
    hwloc_obj_t o = hwloc_get_obj_by_type(t, type, 0);
    return o && o->attr ? static_cast<std::size_t>(o->attr->cache.size) : 0;
}
#endif

Topology detect() {
    Topology topo;
#if defined(SIMDBVH_HAVE_HWLOC)
    if (hwloc_topology_t t = hwloc_topo()) {
        topo.from_hwloc = true;
        topo.physical_cores = hwloc_get_nbobjs_by_type(t, HWLOC_OBJ_CORE);
        topo.logical_cpus = hwloc_get_nbobjs_by_type(t, HWLOC_OBJ_PU);
        topo.l1d_bytes = cache_size(t, HWLOC_OBJ_L1CACHE);
        topo.l2_bytes = cache_size(t, HWLOC_OBJ_L2CACHE);
        topo.l3_bytes = cache_size(t, HWLOC_OBJ_L3CACHE);
        return topo;
    }
#endif
    topo.logical_cpus = static_cast<int>(std::thread::hardware_concurrency());
    topo.l1d_bytes = platform::cache_bytes(1);
    topo.l2_bytes = platform::cache_bytes(2);
    topo.l3_bytes = platform::cache_bytes(3);
    return topo;
}

std::string bytes(std::size_t n) {
    if (n == 0) return "?";
    if (n % (1u << 20) == 0) return std::to_string(n >> 20) + " MiB";
    if (n % (1u << 10) == 0) return std::to_string(n >> 10) + " KiB";
    return std::to_string(n) + " B";
}

}  // namespace

const Topology& topology() {
    static const Topology topo = detect();
    return topo;
}

std::string machine_line() {
    // Built with append() only: GCC 12's -Wrestrict misfires on `"literal" + std::string&&`.
    const Topology& t = topology();
    std::string s(cpu_name());
    s.append(" | ").append(t.physical_cores > 0 ? std::to_string(t.physical_cores) : std::string("?"));
    s.append(" cores, ").append(std::to_string(t.logical_cpus)).append(" threads");
    s.append(" | L1d ").append(bytes(t.l1d_bytes)).append(", L2 ").append(bytes(t.l2_bytes));
    s.append(", L3 ").append(bytes(t.l3_bytes)).append(" | ISAs");
    for (Isa isa : supported_isas()) s.append(" ").append(name(isa));
    try {
        const Isa active = active_isa();
        s.append(" (active ").append(name(active)).append(")");
    } catch (const std::exception&) {
        s.append(" (active: invalid SIMDBVH_ISA)");
    }
    s.append(t.from_hwloc ? " | hwloc" : " | no hwloc");
    return s;
}

bool pin_current_thread_to_core(int core) {
#if defined(SIMDBVH_HAVE_HWLOC)
    hwloc_topology_t t = hwloc_topo();
    if (!t || core < 0) return false;
    hwloc_obj_t o = hwloc_get_obj_by_type(t, HWLOC_OBJ_CORE, static_cast<unsigned>(core));
    if (!o || !o->cpuset) return false;
    return hwloc_set_cpubind(t, o->cpuset, HWLOC_CPUBIND_THREAD) == 0;
#else
    (void)core;
    return false;
#endif
}

}  // namespace simdbvh
