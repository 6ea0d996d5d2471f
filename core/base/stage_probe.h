// Stage probes for the ARM instruction counter (scripts/arm-icount.sh, docs/performance.md): the
// frame path calls stage_probe(i + 1) as its stage i starts and stage_probe(0) when it is done.
// Each slot is an empty out-of-line function of its own, `ale_stage_probe_<slot>`, whose entry the
// counter's qemu plugin recognises by its symbol; everything executed from one probe to the next
// is charged to the first one's slot. A probe computes nothing and changes no result: a table
// load, a call and a return (about four instructions).
#pragma once

#include <cstddef>

#include "core/base/frame_record.h"

namespace ale {

// Slot 0: outside the frame path; slot i + 1: the path's stage i (timings() order).
constexpr std::size_t kStageProbeSlots = kMaxFrameStages + 1;

using StageProbe = void (*)();
extern const StageProbe kStageProbes[kStageProbeSlots];

// A slot >= kStageProbeSlots is ignored.
inline void stage_probe(std::size_t slot) {
  if (slot < kStageProbeSlots) kStageProbes[slot]();
}

// The probes of one run of `stages` stages: slot 1 from construction, next() as each stage ends,
// slot 0 after the last one or, on an early return, at destruction.
class StageProbeRun {
 public:
  explicit StageProbeRun(std::size_t stages) : stages_(stages) { stage_probe(1); }
  ~StageProbeRun() {
    if (done_ < stages_) stage_probe(0);
  }
  StageProbeRun(const StageProbeRun&) = delete;
  StageProbeRun& operator=(const StageProbeRun&) = delete;
  void next() {
    ++done_;
    stage_probe(done_ < stages_ ? done_ + 1 : 0);
  }

 private:
  std::size_t stages_;
  std::size_t done_ = 0;
};

}  // namespace ale
