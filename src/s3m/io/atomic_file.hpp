#pragma once
// Crash-safe file output for the io writers: the helpers live in core (s3m/core/atomic_file.hpp) so
// that modules without io (core's class lists, features' vocabularies) write atomically too.
#include "s3m/core/atomic_file.hpp"

namespace s3m::io {
using s3m::write_bytes_atomic;
using s3m::write_file_atomic;
using s3m::write_text_atomic;
}  // namespace s3m::io
