#include "tally.h"

#include <stdlib.h>
#include <string.h>

#define BLOCKS_PER_CHUNK 4096

int icount_tally_init(struct icount_tally* t, int frame_slot, int by_function) {
  memset(t, 0, sizeof *t);
  if (frame_slot < 0 || frame_slot >= ICOUNT_MAX_SLOTS) return -1;
  t->frame_slot = frame_slot;
  t->by_function = by_function;
  t->hash_cap = 1024;
  t->func_hash = calloc(t->hash_cap, sizeof *t->func_hash);
  return t->func_hash ? 0 : -1;
}

void icount_tally_free(struct icount_tally* t) {
  for (size_t i = 0; i * BLOCKS_PER_CHUNK < t->n_blocks; ++i) free(t->chunks[i]);
  free(t->chunks);
  free(t->frames);
  free(t->funcs);
  free(t->func_hash);
  memset(t, 0, sizeof *t);
}

static uint64_t name_hash(const char* s) {
  uint64_t h = 14695981039346656037ull; /* FNV-1a */
  for (; *s; ++s) h = (h ^ (unsigned char)*s) * 1099511628211ull;
  return h;
}

static int grow(void** p, size_t* cap, size_t need, size_t elem) {
  if (need <= *cap) return 0;
  size_t n = *cap ? *cap : 16;
  while (n < need) n *= 2;
  void* q = realloc(*p, n * elem);
  if (!q) return -1;
  memset((char*)q + *cap * elem, 0, (n - *cap) * elem);
  *p = q;
  *cap = n;
  return 0;
}

static int rehash(struct icount_tally* t) {
  size_t cap = t->hash_cap * 2;
  uint32_t* h = calloc(cap, sizeof *h);
  if (!h) return -1;
  for (size_t i = 0; i < t->n_funcs; ++i) {
    size_t k = name_hash(t->funcs[i].name) & (cap - 1);
    while (h[k]) k = (k + 1) & (cap - 1);
    h[k] = (uint32_t)(i + 1);
  }
  free(t->func_hash);
  t->func_hash = h;
  t->hash_cap = cap;
  return 0;
}

uint32_t icount_tally_function(struct icount_tally* t, const char* name) {
  if (!name || !*name) name = "?";
  size_t k = name_hash(name) & (t->hash_cap - 1);
  for (; t->func_hash[k]; k = (k + 1) & (t->hash_cap - 1)) {
    const uint32_t i = t->func_hash[k] - 1;
    if (t->funcs[i].name == name || strcmp(t->funcs[i].name, name) == 0) return i;
  }
  if (grow((void**)&t->funcs, &t->cap_funcs, t->n_funcs + 1, sizeof *t->funcs)) return UINT32_MAX;
  const uint32_t i = (uint32_t)t->n_funcs++;
  t->funcs[i].name = name;
  t->func_hash[k] = i + 1;
  if (2 * t->n_funcs > t->hash_cap && rehash(t)) return UINT32_MAX;
  return i;
}

struct icount_block* icount_tally_block(struct icount_tally* t, uint32_t insns, uint32_t func) {
  const size_t chunk = t->n_blocks / BLOCKS_PER_CHUNK;
  if (t->n_blocks % BLOCKS_PER_CHUNK == 0) {
    if (grow((void**)&t->chunks, &t->cap_chunks, chunk + 1, sizeof *t->chunks)) return NULL;
    t->chunks[chunk] = calloc(BLOCKS_PER_CHUNK, sizeof(struct icount_block));
    if (!t->chunks[chunk]) return NULL;
  }
  struct icount_block* b = &t->chunks[chunk][t->n_blocks % BLOCKS_PER_CHUNK];
  ++t->n_blocks;
  b->insns = insns;
  b->func = func;
  return b;
}

/* Charges every block's starts since the last switch to the current slot's functions. */
static void charge_functions(struct icount_tally* t) {
  const int s = t->current;
  for (size_t i = 0; i < t->n_blocks; ++i) {
    struct icount_block* b = &t->chunks[i / BLOCKS_PER_CHUNK][i % BLOCKS_PER_CHUNK];
    const uint64_t d = b->execs - b->seen;
    if (d) {
      t->funcs[b->func].slot[s] += d * b->insns;
      b->seen = b->execs;
    }
  }
}

static void charge(struct icount_tally* t) {
  const uint64_t d = t->total - t->at_switch;
  t->at_switch = t->total;
  t->slot[t->current] += d;
  if (t->n_frames)
    t->frames[(t->n_frames - 1) * ICOUNT_MAX_SLOTS + (size_t)t->current] += d;
  else
    t->prologue += d;
  if (t->by_function) charge_functions(t);
}

void icount_tally_switch(struct icount_tally* t, int slot) {
  charge(t);
  if (slot < 0 || slot >= ICOUNT_MAX_SLOTS) {
    ++t->unknown_probes;
    slot = 0;
  }
  /* out of memory: the new frame's counts go on into the last row */
  if (slot == t->frame_slot &&
      grow((void**)&t->frames, &t->cap_frames, t->n_frames + 1, sizeof(uint64_t) * ICOUNT_MAX_SLOTS) == 0)
    ++t->n_frames;
  t->current = slot;
}

void icount_tally_finish(struct icount_tally* t) { charge(t); }

static int by_count_desc(const void* a, const void* b) {
  const uint64_t* x = a;
  const uint64_t* y = b;
  if (x[0] != y[0]) return x[0] < y[0] ? 1 : -1;
  return x[1] < y[1] ? -1 : x[1] > y[1];
}

int icount_tally_write(const struct icount_tally* t, FILE* report, FILE* frames) {
  fprintf(report, "total_instructions %llu\n", (unsigned long long)t->total);
  fprintf(report, "frames %zu\nprologue %llu\nframe_slot %d\n", t->n_frames, (unsigned long long)t->prologue,
          t->frame_slot);
  if (t->unknown_probes) fprintf(report, "unknown_probes %llu\n", (unsigned long long)t->unknown_probes);
  for (int s = 0; s < ICOUNT_MAX_SLOTS; ++s)
    if (t->slot[s]) fprintf(report, "slot %d %llu\n", s, (unsigned long long)t->slot[s]);
  if (t->by_function) {
    /* per slot, the functions by count (pairs of count and index, sorted) */
    uint64_t* order = malloc(2 * (t->n_funcs ? t->n_funcs : 1) * sizeof *order);
    if (!order) return -1;
    for (int s = 0; s < ICOUNT_MAX_SLOTS; ++s) {
      size_t n = 0;
      for (size_t i = 0; i < t->n_funcs; ++i)
        if (t->funcs[i].slot[s]) {
          order[2 * n] = t->funcs[i].slot[s];
          order[2 * n + 1] = i;
          ++n;
        }
      qsort(order, n, 2 * sizeof *order, by_count_desc);
      for (size_t k = 0; k < n; ++k)
        fprintf(report, "function %d %llu %s\n", s, (unsigned long long)order[2 * k], t->funcs[order[2 * k + 1]].name);
    }
    free(order);
  }
  if (frames) {
    fprintf(frames, "frame");
    for (int s = 0; s < ICOUNT_MAX_SLOTS; ++s) fprintf(frames, ",slot%d", s);
    fprintf(frames, "\n");
    for (size_t f = 0; f < t->n_frames; ++f) {
      fprintf(frames, "%zu", f);
      for (int s = 0; s < ICOUNT_MAX_SLOTS; ++s)
        fprintf(frames, ",%llu", (unsigned long long)t->frames[f * ICOUNT_MAX_SLOTS + (size_t)s]);
      fprintf(frames, "\n");
    }
    if (ferror(frames)) return -1;
  }
  return ferror(report) ? -1 : 0;
}
