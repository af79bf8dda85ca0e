/// \file gz_file.h
/// \brief A zlib file handle closed on every path (private to dlo_formats).
#pragma once

#include <zlib.h>

#include <string>

namespace dlo {

/// A gzip file (or, read, a plain one: zlib reads those through), closed on every path.
struct GzFile {
  gzFile file;
  /// `mode` as gzopen()'s: "rb", or "wb1" to write at zlib's fastest level.
  explicit GzFile(const std::string& path, const char* mode = "rb")
      : file(gzopen(path.c_str(), mode)) {}
  ~GzFile() {
    if (file) gzclose(file);
  }
  GzFile(const GzFile&) = delete;
  GzFile& operator=(const GzFile&) = delete;
};

}  // namespace dlo
