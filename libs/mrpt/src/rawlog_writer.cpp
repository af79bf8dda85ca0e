#include "dlo/mrpt/rawlog_writer.h"

#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/io/CFileOutputStream.h>

#include "dlo/files/error.h"

namespace dlo {

RawlogWriter::RawlogWriter(const std::string& path) : output_(path) {
  const bool gz = path.size() >= 3 && path.compare(path.size() - 3, 3, ".gz") == 0;
  if (gz) {
    auto out = std::make_unique<mrpt::io::CFileGZOutputStream>();
    if (!out->open(output_.temp())) {
      throw OutputError("cannot create '" + output_.temp() + "' (is the folder writable?).");
    }
    archive_ = mrpt::serialization::archiveUniquePtrFrom(*out);
    out_ = std::move(out);
  } else {
    auto out = std::make_unique<mrpt::io::CFileOutputStream>();
    if (!out->open(output_.temp())) {
      throw OutputError("cannot create '" + output_.temp() + "' (is the folder writable?).");
    }
    archive_ = mrpt::serialization::archiveUniquePtrFrom(*out);
    out_ = std::move(out);
  }
}

RawlogWriter::~RawlogWriter() {
  // Flushed and closed before output_ renames or removes the file.
  archive_.reset();
  out_.reset();
}

void RawlogWriter::write(const mrpt::serialization::CSerializable& entry) {
  archive_->WriteObject(&entry);
  ++count_;
  output_.setKeepPartial(true);
}

void RawlogWriter::commit() {
  archive_.reset();
  out_.reset();
  output_.commit();
}

}  // namespace dlo
