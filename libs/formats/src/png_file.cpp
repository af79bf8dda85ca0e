#include "dlo/formats/png_file.h"

#include <opencv2/imgcodecs.hpp>

#include "dlo/files/atomic_file.h"

namespace dlo {

void writePng(const cv::Mat& image, const std::string& path) {
  std::vector<unsigned char> bytes;
  bool ok = false;
  try {
    ok = !image.empty() && cv::imencode(".png", image, bytes);
  } catch (const cv::Exception&) {
    ok = false;
  }
  if (!ok) throw OutputError("cannot write '" + path + "' (the image could not be encoded).");
  writeBytesAtomically(path, bytes);
}

}  // namespace dlo
