// The map store's configuration keys (core/base/config_table.h; the daemon's `slam.capacity.*`).
#pragma once

#include "core/base/config_table.h"
#include "core/map/map_store.h"

namespace ale::map {

extern const ConfigTable kMapCapacityConfig;

}  // namespace ale::map
