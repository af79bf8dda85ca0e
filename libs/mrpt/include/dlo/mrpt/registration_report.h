/// \file registration_report.h
/// \brief One registration result as a JSON object, for tools and scripts.
#pragma once

#include <mrpt/poses/CPose3DPDFGaussian.h>
#include <string>

#include "dlo/mrpt/CDirectHeightAligner.h"

namespace dlo {

/// The result of a registration as one JSON object on one line:
/// `{"pose": {"x", "y", "z", "yaw_deg", "pitch_deg", "roll_deg"}, "covariance": [36 numbers,
/// row-major, order x y z yaw pitch roll, metres and radians as in MRPT], "iterations", "cells",
/// "rms_height_error", "degenerate", "converged", "information_ratio", "time_ms": {"grid",
/// "gradients", "selection", "solve", "total"}}`. Non-finite numbers are written as null, which
/// JSON can carry.
std::string registrationReportJson(const mrpt::poses::CPose3DPDFGaussian& pdf,
                                   const mrpt::slam::CDirectHeightAligner::TReturnInfo& info);

}  // namespace dlo
