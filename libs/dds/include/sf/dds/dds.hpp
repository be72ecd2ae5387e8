// The dds module in one include.
#pragma once

#include "sf/dds/config.hpp"
#include "sf/dds/entity.hpp"
#include "sf/dds/executor.hpp"
#include "sf/dds/introspection.hpp"
#include "sf/dds/participant.hpp"
#include "sf/dds/qos.hpp"
#include "sf/dds/reader.hpp"
#include "sf/dds/status.hpp"
#include "sf/dds/topic.hpp"
#include "sf/dds/writer.hpp"
