#include "core/base/memory_pool.h"

#include <new>

namespace ale {

void BlockPool::AlignedDelete::operator()(std::uint8_t* p) const {
  ::operator delete[](p, std::align_val_t(kAlignment));
}

BlockPool::BlockPool(std::string name, std::size_t block_bytes, std::size_t block_count)
    : name_(std::move(name)) {
  stats_.block_bytes = (block_bytes + kAlignment - 1) / kAlignment * kAlignment;
  stats_.capacity = block_count;
  if (stats_.block_bytes > 0 && block_count > 0) {
    arena_.reset(static_cast<std::uint8_t*>(
        ::operator new[](stats_.block_bytes * block_count, std::align_val_t(kAlignment))));
  }
  free_list_.reserve(block_count);
  // Hand out low addresses first: block 0 is on top of the stack.
  for (std::size_t i = block_count; i-- > 0;) free_list_.push_back(static_cast<std::uint32_t>(i));
  used_.assign(block_count, 0);
}

bool BlockPool::owns(const void* p) const {
  if (!arena_) return false;
  auto* b = static_cast<const std::uint8_t*>(p);
  return b >= arena_.get() && b < arena_.get() + stats_.block_bytes * stats_.capacity;
}

Result<void*> BlockPool::allocate() {
  if (free_list_.empty() || !arena_) {
    ++stats_.failures;
    return out_of_memory("pool '" + name_ + "' exhausted (" + std::to_string(stats_.capacity) + " blocks of " +
                         std::to_string(stats_.block_bytes) + " bytes)");
  }
  const std::uint32_t i = free_list_.back();
  free_list_.pop_back();
  used_[i] = 1;
  ++stats_.in_use;
  ++stats_.allocations;
  if (stats_.in_use > stats_.high_water) stats_.high_water = stats_.in_use;
  return static_cast<void*>(arena_.get() + static_cast<std::size_t>(i) * stats_.block_bytes);
}

Status BlockPool::free(void* block) {
  if (!owns(block)) {
    ++stats_.bad_frees;
    return invalid_argument("pool '" + name_ + "': free of a pointer it does not own");
  }
  const std::size_t offset = static_cast<std::size_t>(static_cast<std::uint8_t*>(block) - arena_.get());
  const std::size_t i = offset / stats_.block_bytes;
  if (offset % stats_.block_bytes != 0 || used_[i] == 0) {
    ++stats_.bad_frees;
    return invalid_argument("pool '" + name_ + "': free of a block that is not handed out");
  }
  used_[i] = 0;
  free_list_.push_back(static_cast<std::uint32_t>(i));
  --stats_.in_use;
  return {};
}

}  // namespace ale
