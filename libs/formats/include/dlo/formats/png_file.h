/// \file png_file.h
/// \brief Writing an image as PNG, atomically.
#pragma once

#include <opencv2/core/mat.hpp>
#include <string>

namespace dlo {

/// Encodes `image` (8-bit BGR or grey) as PNG and writes it atomically (see writeAtomically();
/// cv::imwrite would pick the format from the ".tmp" extension of the temporary file).
/// \throws OutputError naming `path`.
void writePng(const cv::Mat& image, const std::string& path);

}  // namespace dlo
