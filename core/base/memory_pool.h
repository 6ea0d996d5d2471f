// A fixed-capacity pool of equal-sized blocks carved from one arena reserved at start-up.
// O(1) allocate and free, no fallback to malloc: exhaustion is an error the caller sees.
// Not thread-safe: the per-frame path runs on one thread.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/base/status.h"

namespace ale {

struct PoolStats {
  std::size_t block_bytes = 0;
  std::size_t capacity = 0;     // blocks in the arena
  std::size_t in_use = 0;       // blocks handed out now
  std::size_t high_water = 0;   // most blocks ever handed out at once
  std::uint64_t allocations = 0;
  std::uint64_t failures = 0;   // allocate() calls refused because the pool was full
  std::uint64_t bad_frees = 0;  // free() calls with a foreign or already-free pointer
};

class BlockPool {
 public:
  static constexpr std::size_t kAlignment = 64;

  // Reserves block_count blocks of block_bytes (rounded up to kAlignment) each; `name` appears
  // in error messages. Both may be 0 (a pool that refuses everything).
  BlockPool(std::string name, std::size_t block_bytes, std::size_t block_count);
  BlockPool(const BlockPool&) = delete;
  BlockPool& operator=(const BlockPool&) = delete;

  // A block of block_bytes(), aligned to kAlignment; kOutOfMemory when none is free.
  Result<void*> allocate();
  // Gives a block back. kInvalidArgument (and nothing changes) if `block` is not a block of this
  // pool or is already free.
  Status free(void* block);

  std::size_t block_bytes() const { return stats_.block_bytes; }
  const PoolStats& stats() const { return stats_; }
  const std::string& name() const { return name_; }
  bool owns(const void* p) const;

 private:
  struct AlignedDelete {
    void operator()(std::uint8_t* p) const;
  };
  std::string name_;
  std::unique_ptr<std::uint8_t[], AlignedDelete> arena_;
  std::vector<std::uint32_t> free_list_;  // stack of free block indices
  std::vector<std::uint8_t> used_;        // 1 while a block is handed out
  PoolStats stats_;
};

}  // namespace ale
