#include "core/place/embedded/embedded_vocabulary.h"

// Defined by the generated embedded_vocabulary_data.cpp.
extern "C" const std::uint8_t ale_embedded_vocabulary_begin[];
extern "C" const std::uint8_t ale_embedded_vocabulary_end[];

namespace ale::place {

Span<const std::uint8_t> embedded_vocabulary_bytes() {
  return Span<const std::uint8_t>(ale_embedded_vocabulary_begin,
                                  static_cast<int>(ale_embedded_vocabulary_end - ale_embedded_vocabulary_begin));
}

Result<Vocabulary> load_embedded_vocabulary() {
  const Span<const std::uint8_t> bytes = embedded_vocabulary_bytes();
  return Vocabulary::parse(bytes.data(), static_cast<std::size_t>(bytes.size()));
}

}  // namespace ale::place
