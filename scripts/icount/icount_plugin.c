/* A qemu TCG plugin that counts the guest instructions an armhf program executes, per stage and
 * per function: the fast counter behind scripts/arm-icount.sh (docs/performance.md). It counts
 * what ../shared/tools/arm_icount.py counts (every start of a translated block adds the block's
 * instructions), with inline adds instead of qemu's exec log, at qemu's normal speed.
 *
 * Arguments (-plugin libicount.so,ARG=VALUE,...):
 *   out=FILE        the report (tally.h: icount_tally_write); required
 *   frames=FILE     one CSV row of per-slot counts per frame
 *   functions=on    per-slot counts by function (the block's first instruction's symbol, as
 *                   arm_icount.py's --top); a pass over all blocks at every probe
 *   probe=PREFIX    symbol prefix of the probes (default ale_stage_probe_): a block starting in
 *                   PREFIX<N> switches to slot N
 *   frame_slot=N    the slot whose probe starts a frame (default 1)
 */
#include <inttypes.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <qemu-plugin.h>

#include "tally.h"

QEMU_PLUGIN_EXPORT int qemu_plugin_version = QEMU_PLUGIN_VERSION;

static struct icount_tally tally;
static pthread_mutex_t lock = PTHREAD_MUTEX_INITIALIZER;
static const char* out_path;
static const char* frames_path;
static const char* probe_prefix = "ale_stage_probe_";
static size_t probe_prefix_len;
static int vcpus;
static int failed;

static void on_probe(unsigned int vcpu, void* slot) {
  (void)vcpu;
  pthread_mutex_lock(&lock);
  icount_tally_switch(&tally, (int)(intptr_t)slot);
  pthread_mutex_unlock(&lock);
}

/* The slot of a probe symbol, or -1 when `sym` is not one. */
static int probe_slot(const char* sym) {
  if (!sym || strncmp(sym, probe_prefix, probe_prefix_len) != 0) return -1;
  const char* digits = sym + probe_prefix_len;
  if (!*digits) return -1;
  char* end;
  const long slot = strtol(digits, &end, 10);
  return *end || slot < 0 || slot > 1000000 ? -1 : (int)slot;
}

static void on_translate(qemu_plugin_id_t id, struct qemu_plugin_tb* tb) {
  (void)id;
  const size_t n = qemu_plugin_tb_n_insns(tb);
  if (n == 0) return;
  const char* sym = qemu_plugin_insn_symbol(qemu_plugin_tb_get_insn(tb, 0));
  pthread_mutex_lock(&lock);
  qemu_plugin_register_vcpu_tb_exec_inline(tb, QEMU_PLUGIN_INLINE_ADD_U64, &tally.total, n);
  if (tally.by_function) {
    const uint32_t f = icount_tally_function(&tally, sym);
    struct icount_block* b = f == UINT32_MAX ? NULL : icount_tally_block(&tally, (uint32_t)n, f);
    if (b)
      qemu_plugin_register_vcpu_tb_exec_inline(tb, QEMU_PLUGIN_INLINE_ADD_U64, &b->execs, 1);
    else
      failed = 1;
  }
  pthread_mutex_unlock(&lock);
  const int slot = probe_slot(sym);
  if (slot >= 0)
    qemu_plugin_register_vcpu_tb_exec_cb(tb, on_probe, QEMU_PLUGIN_CB_NO_REGS, (void*)(intptr_t)slot);
}

static void on_vcpu_init(qemu_plugin_id_t id, unsigned int vcpu) {
  (void)id;
  (void)vcpu;
  pthread_mutex_lock(&lock);
  ++vcpus;
  pthread_mutex_unlock(&lock);
}

static void on_atexit(qemu_plugin_id_t id, void* p) {
  (void)id;
  (void)p;
  pthread_mutex_lock(&lock);
  icount_tally_finish(&tally);
  FILE* report = fopen(out_path, "w");
  FILE* frames = frames_path ? fopen(frames_path, "w") : NULL;
  if (!report || (frames_path && !frames)) {
    fprintf(stderr, "icount: cannot write %s\n", !report ? out_path : frames_path);
  } else {
    /* Inline adds from several host threads race: the counts are exact for one thread only. */
    fprintf(report, "vcpus %d\n", vcpus);
    if (failed) fprintf(report, "error out_of_memory\n");
    if (icount_tally_write(&tally, report, frames)) fprintf(stderr, "icount: write error\n");
  }
  if (report) fclose(report);
  if (frames) fclose(frames);
  pthread_mutex_unlock(&lock);
}

QEMU_PLUGIN_EXPORT int qemu_plugin_install(qemu_plugin_id_t id, const qemu_info_t* info, int argc, char** argv) {
  int frame_slot = 1;
  bool functions = false;
  for (int i = 0; i < argc; ++i) {
    const char* a = argv[i];
    const char* eq = strchr(a, '=');
    if (!eq) {
      fprintf(stderr, "icount: argument '%s' is not KEY=VALUE\n", a);
      return -1;
    }
    const size_t k = (size_t)(eq - a);
    const char* v = eq + 1;
    if (k == 3 && !strncmp(a, "out", k)) {
      out_path = v;
    } else if (k == 6 && !strncmp(a, "frames", k)) {
      frames_path = v;
    } else if (k == 9 && !strncmp(a, "functions", k)) {
      if (!qemu_plugin_bool_parse("functions", v, &functions)) {
        fprintf(stderr, "icount: functions=%s: expected on or off\n", v);
        return -1;
      }
    } else if (k == 5 && !strncmp(a, "probe", k)) {
      probe_prefix = v;
    } else if (k == 10 && !strncmp(a, "frame_slot", k)) {
      char* end;
      frame_slot = (int)strtol(v, &end, 10);
      if (*end || !*v || frame_slot < 0 || frame_slot >= ICOUNT_MAX_SLOTS) {
        fprintf(stderr, "icount: frame_slot=%s: expected 0..%d\n", v, ICOUNT_MAX_SLOTS - 1);
        return -1;
      }
    } else {
      fprintf(stderr, "icount: unknown argument '%s'\n", a);
      return -1;
    }
  }
  if (!out_path) {
    fprintf(stderr, "icount: out=FILE is required\n");
    return -1;
  }
  if (info->system_emulation) {
    fprintf(stderr, "icount: for qemu's user mode only\n");
    return -1;
  }
  probe_prefix_len = strlen(probe_prefix);
  if (icount_tally_init(&tally, frame_slot, functions)) {
    fprintf(stderr, "icount: out of memory\n");
    return -1;
  }
  qemu_plugin_register_vcpu_init_cb(id, on_vcpu_init);
  qemu_plugin_register_vcpu_tb_trans_cb(id, on_translate);
  qemu_plugin_register_atexit_cb(id, on_atexit, NULL);
  return 0;
}
