#include "core/base/stage_probe.h"

// noipa: never inlined, cloned or folded into one another (identical bodies), so that each slot
// keeps its own address and symbol.
#if defined(__GNUC__) && !defined(__clang__)
#define ALE_PROBE_ATTR __attribute__((noipa, used))
#else
#define ALE_PROBE_ATTR __attribute__((noinline, used))
#endif
#define ALE_PROBE(n) \
  extern "C" ALE_PROBE_ATTR void ale_stage_probe_##n() { asm volatile("" ::: "memory"); }

ALE_PROBE(0)
ALE_PROBE(1)
ALE_PROBE(2)
ALE_PROBE(3)
ALE_PROBE(4)
ALE_PROBE(5)
ALE_PROBE(6)
ALE_PROBE(7)
ALE_PROBE(8)
ALE_PROBE(9)
ALE_PROBE(10)
ALE_PROBE(11)
ALE_PROBE(12)
ALE_PROBE(13)
ALE_PROBE(14)
ALE_PROBE(15)
ALE_PROBE(16)

namespace ale {

static_assert(kStageProbeSlots == 17, "one ALE_PROBE above for each slot");

const StageProbe kStageProbes[kStageProbeSlots] = {
    ale_stage_probe_0,  ale_stage_probe_1,  ale_stage_probe_2,  ale_stage_probe_3,  ale_stage_probe_4,
    ale_stage_probe_5,  ale_stage_probe_6,  ale_stage_probe_7,  ale_stage_probe_8,  ale_stage_probe_9,
    ale_stage_probe_10, ale_stage_probe_11, ale_stage_probe_12, ale_stage_probe_13, ale_stage_probe_14,
    ale_stage_probe_15, ale_stage_probe_16};

}  // namespace ale
