#include "dlo/mrpt/rawlog_writer.h"

#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/io/CFileOutputStream.h>
#include <filesystem>

#include "dlo/mrpt/input_error.h"

namespace dlo {

namespace fs = std::filesystem;

RawlogWriter::RawlogWriter(const std::string& path) : path_(path), temp_path_(path + ".tmp") {
  const bool gz = path.size() >= 3 && path.compare(path.size() - 3, 3, ".gz") == 0;
  if (gz) {
    auto out = std::make_unique<mrpt::io::CFileGZOutputStream>();
    if (!out->open(temp_path_)) {
      throw InputError("cannot create '" + temp_path_ + "' (is the folder writable?).");
    }
    archive_ = mrpt::serialization::archiveUniquePtrFrom(*out);
    out_ = std::move(out);
  } else {
    auto out = std::make_unique<mrpt::io::CFileOutputStream>();
    if (!out->open(temp_path_)) {
      throw InputError("cannot create '" + temp_path_ + "' (is the folder writable?).");
    }
    archive_ = mrpt::serialization::archiveUniquePtrFrom(*out);
    out_ = std::move(out);
  }
}

RawlogWriter::~RawlogWriter() {
  if (committed_) return;
  archive_.reset();
  out_.reset();  // flushes and closes
  std::error_code ec;
  if (count_ > 0) {
    fs::rename(temp_path_, partialPath(), ec);
  } else {
    fs::remove(temp_path_, ec);
  }
}

void RawlogWriter::write(const mrpt::obs::CObservation& obs) {
  archive_->WriteObject(&obs);
  ++count_;
}

void RawlogWriter::commit() {
  archive_.reset();
  out_.reset();
  std::error_code ec;
  fs::rename(temp_path_, path_, ec);
  if (ec) {
    throw InputError("cannot rename '" + temp_path_ + "' to '" + path_ + "': " + ec.message() +
                     ".");
  }
  committed_ = true;
}

}  // namespace dlo
