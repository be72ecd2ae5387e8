// Everything of the OPC UA binary encoding layer in one include: built-in types, Variant and
// friends, the encoder/decoder, status codes, namespace-0 NodeIds, the generated structures and
// the service-message envelope.
#pragma once

#include "sf/opcua/binary.hpp"              // IWYU pragma: export
#include "sf/opcua/builtin_types.hpp"       // IWYU pragma: export
#include "sf/opcua/codec.hpp"               // IWYU pragma: export
#include "sf/opcua/containers.hpp"          // IWYU pragma: export
#include "sf/opcua/extension_registry.hpp"  // IWYU pragma: export
#include "sf/opcua/messages.hpp"            // IWYU pragma: export
#include "sf/opcua/node_ids.hpp"            // IWYU pragma: export
#include "sf/opcua/status_code.hpp"         // IWYU pragma: export
#include "sf/opcua/status_codes.hpp"        // IWYU pragma: export
#include "sf/opcua/types.hpp"               // IWYU pragma: export
#include "sf/opcua/variant.hpp"             // IWYU pragma: export
