// The vocabulary built into the binary at build time (data/vocabulary/, docs/place.md): the
// default of the daemon when no vocabulary file is configured. A library of its own
// (ale_core_place_embedded) so that only what links it carries the bytes.
#pragma once

#include <cstdint>

#include "core/base/span.h"
#include "core/base/status.h"
#include "core/place/vocabulary.h"

namespace ale::place {

// The file's bytes as built in.
Span<const std::uint8_t> embedded_vocabulary_bytes();
// Vocabulary::parse() of them (the same checks as a file gets).
Result<Vocabulary> load_embedded_vocabulary();

}  // namespace ale::place
