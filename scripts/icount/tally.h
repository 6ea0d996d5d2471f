/* The bookkeeping of the ARM instruction counter (scripts/arm-icount.sh), apart from qemu so that a
 * host test can drive it. qemu adds each translated block's instruction count to `total` and one
 * to the block's `execs` every time the block starts (inline, no call); the probe callbacks call
 * tally_switch(). Counting block starts times block lengths is what ../shared/tools/arm_icount.py
 * does from qemu's exec log, so the two agree exactly (a block left early by a signal counts
 * whole in both).
 *
 * Slots: the probed program calls ale_stage_probe_<slot>() as a stage starts
 * (core/base/stage_probe.h); everything executed from there to the next probe is charged to that
 * slot. Slot 0 is the start-up before the first probe and anything outside the probed stages.
 * Frames: each entry of `frame_slot` starts a new row of per-slot counts; what ran before the
 * first one is the prologue. */
#ifndef ALE_ICOUNT_TALLY_H
#define ALE_ICOUNT_TALLY_H

#include <stdint.h>
#include <stdio.h>

#ifdef __cplusplus
extern "C" {
#endif

#define ICOUNT_MAX_SLOTS 32

/* One translation of a guest block. Its address is stable for the tally's life: qemu's inline ops
 * point at `execs`. */
struct icount_block {
  uint64_t execs; /* starts of the block, added by qemu */
  uint64_t seen;  /* execs already charged to a slot's functions */
  uint32_t insns; /* guest instructions in the block */
  uint32_t func;  /* index into the tally's functions */
};

struct icount_tally {
  uint64_t total; /* guest instructions so far, added by qemu */
  int frame_slot;
  int by_function; /* charge functions per slot at each switch (costs a pass over the blocks) */
  int current;     /* the slot running now */
  uint64_t at_switch; /* total at the last switch */
  uint64_t slot[ICOUNT_MAX_SLOTS];
  uint64_t prologue; /* instructions before the first frame */
  uint64_t unknown_probes; /* probes of a slot >= ICOUNT_MAX_SLOTS (counted, charged to slot 0) */
  /* frames: rows of ICOUNT_MAX_SLOTS counts */
  uint64_t* frames;
  size_t n_frames, cap_frames; /* rows */
  /* blocks, in chunks so that their addresses never move */
  struct icount_block** chunks;
  size_t n_blocks, cap_chunks;
  /* functions: name (interned by pointer, then by text) and per-slot counts */
  struct icount_function* funcs;
  size_t n_funcs, cap_funcs;
  uint32_t* func_hash; /* open addressing over names' text: index + 1, 0 = empty */
  size_t hash_cap;
};

struct icount_function {
  const char* name;
  uint64_t slot[ICOUNT_MAX_SLOTS];
};

/* 0 on success, -1 when out of memory or frame_slot is out of range. */
int icount_tally_init(struct icount_tally* t, int frame_slot, int by_function);
void icount_tally_free(struct icount_tally* t);
/* The index of function `name` (NULL: "?"); the tally keeps the pointer, which must outlive it.
 * UINT32_MAX when out of memory. */
uint32_t icount_tally_function(struct icount_tally* t, const char* name);
/* A new block of `insns` instructions in function `func`; NULL when out of memory. */
struct icount_block* icount_tally_block(struct icount_tally* t, uint32_t insns, uint32_t func);
/* A probe of `slot` ran: what ran since the last switch goes to the current slot. */
void icount_tally_switch(struct icount_tally* t, int slot);
/* At the end: charges what ran since the last switch. */
void icount_tally_finish(struct icount_tally* t);
/* The report (docs/performance.md, "whole pipeline"): totals, slots, functions; and one CSV row
 * per frame when `frames` is not NULL. 0 on success, -1 on a write error. */
int icount_tally_write(const struct icount_tally* t, FILE* report, FILE* frames);

#ifdef __cplusplus
}
#endif

#endif
