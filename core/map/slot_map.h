// A fixed-capacity container of objects keyed by typed ids: the storage of the map store.
// Capacity is reserved at construction and never grows (the firmware's memory budget); a full
// container refuses inserts with kOutOfMemory. An id is a slot index and that slot's generation,
// so an id kept after its object was erased is recognised as stale instead of reaching the
// slot's next occupant. Slots are reused last-freed first, so the same sequence of calls gives
// the same ids on every run.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/base/status.h"

namespace ale::map {

template <class Tag>
struct Id {
  static constexpr std::uint32_t kInvalid = 0xFFFFFFFFu;
  static constexpr int kSlotBits = 20;  // up to ~1M objects of a kind
  static constexpr std::uint32_t kSlotMask = (1u << kSlotBits) - 1u;

  std::uint32_t value = kInvalid;

  bool valid() const { return value != kInvalid; }
  std::uint32_t slot() const { return value & kSlotMask; }
  std::uint32_t generation() const { return value >> kSlotBits; }
  static Id make(std::uint32_t slot, std::uint32_t generation) {
    return Id{(generation << kSlotBits) | (slot & kSlotMask)};
  }
  friend bool operator==(Id a, Id b) { return a.value == b.value; }
  friend bool operator!=(Id a, Id b) { return a.value != b.value; }
  friend bool operator<(Id a, Id b) { return a.value < b.value; }
};

template <class T, class IdT>
class SlotMap {
 public:
  // `name` appears in error messages.
  SlotMap(std::string name, std::size_t capacity) : name_(std::move(name)) {
    if (capacity > IdT::kSlotMask) capacity = IdT::kSlotMask;
    slots_.resize(capacity);
    free_.reserve(capacity);
    for (std::size_t i = capacity; i > 0; --i) free_.push_back(static_cast<std::uint32_t>(i - 1));
  }

  // Stores `value`; kOutOfMemory naming the container when every slot is taken.
  Result<IdT> insert(T value) {
    if (free_.empty()) {
      ++failures_;
      return out_of_memory(name_ + ": all " + std::to_string(slots_.size()) + " slots in use");
    }
    const std::uint32_t s = free_.back();
    free_.pop_back();
    Slot& slot = slots_[s];
    slot.value.emplace(std::move(value));
    ++size_;
    if (size_ > high_water_) high_water_ = size_;
    return IdT::make(s, slot.generation);
  }

  // The object, or nullptr when the id is invalid, stale or erased.
  T* get(IdT id) {
    if (!id.valid() || id.slot() >= slots_.size()) return nullptr;
    Slot& slot = slots_[id.slot()];
    return slot.value && slot.generation == id.generation() ? &*slot.value : nullptr;
  }
  const T* get(IdT id) const { return const_cast<SlotMap*>(this)->get(id); }
  bool contains(IdT id) const { return get(id) != nullptr; }

  // false when the id does not name a live object.
  bool erase(IdT id) {
    if (!contains(id)) return false;
    Slot& slot = slots_[id.slot()];
    slot.value.reset();
    slot.generation = (slot.generation + 1) & (0xFFFFFFFFu >> IdT::kSlotBits);
    // generation 0xFFF... with every slot bit set would be kInvalid: skip that generation
    if (IdT::make(id.slot(), slot.generation).value == IdT::kInvalid) slot.generation = 0;
    free_.push_back(id.slot());
    --size_;
    return true;
  }

  void clear() {
    for (std::uint32_t s = 0; s < slots_.size(); ++s) {
      if (slots_[s].value) erase(IdT::make(s, slots_[s].generation));
    }
  }

  // Calls f(id, object) for every live object in slot order.
  template <class F>
  void for_each(F&& f) {
    for (std::uint32_t s = 0; s < slots_.size(); ++s) {
      if (slots_[s].value) f(IdT::make(s, slots_[s].generation), *slots_[s].value);
    }
  }
  template <class F>
  void for_each(F&& f) const {
    for (std::uint32_t s = 0; s < slots_.size(); ++s) {
      if (slots_[s].value) f(IdT::make(s, slots_[s].generation), *slots_[s].value);
    }
  }

  // The id of the object in a slot, invalid when the slot is free.
  IdT id_at_slot(std::uint32_t s) const {
    return s < slots_.size() && slots_[s].value ? IdT::make(s, slots_[s].generation) : IdT{};
  }

  std::size_t size() const { return size_; }
  std::size_t capacity() const { return slots_.size(); }
  std::size_t high_water() const { return high_water_; }
  std::uint64_t failures() const { return failures_; }

 private:
  struct Slot {
    std::optional<T> value;
    std::uint32_t generation = 0;
  };
  std::string name_;
  std::vector<Slot> slots_;
  std::vector<std::uint32_t> free_;  // stack: last freed is reused first
  std::size_t size_ = 0;
  std::size_t high_water_ = 0;
  std::uint64_t failures_ = 0;
};

}  // namespace ale::map
