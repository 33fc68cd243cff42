#pragma once
// The wiring check of a built run: every entry a module reads must be written by the module that
// feeds its container (raw: the source, when it declares its entries; measurement: a
// preprocessor; scene: a tracker slice), with the same value type. Run by `validate`, `run` and
// the shell before the first frame, so a misspelt entry name fails at once instead of every
// frame failing to track.
#include "config_builder.h"
#include "run_config.h"

namespace plugslam::runtime {

/// Reports each wiring error through `builder` (file:line:col of the key, its pipeline path, what
/// writes that container, a did-you-mean); the caller then throws them with builder.check().
void checkEntries(const RunConfig& run, const ConfigDocument& doc, ConfigBuilder& builder);

}  // namespace plugslam::runtime
