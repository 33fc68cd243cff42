#pragma once
// The viewer stream's wire format: each drawable as JSON in the layout of its @foxglove/schemas
// schema (binary fields in base64, times as {sec, nsec}), and the JSON schemas advertised for
// them. One encoding for the WebSocket server and the MCAP recordings.
#include <cstddef>
#include <string>

#include "plugslam/view/drawables.h"

namespace plugslam::runtime {

/// The schema name of Drawable alternative `kind` ("foxglove.PointCloud", "plugslam.Status").
std::string schemaName(size_t kind);
/// The JSON schema (draft 2020-12 text) of Drawable alternative `kind`.
std::string jsonSchema(size_t kind);
/// The drawable as JSON text.
std::string encodeJson(const view::Drawable& drawable);
/// Standard base64 (with padding) of `size` bytes.
std::string base64(const void* data, size_t size);

}  // namespace plugslam::runtime
