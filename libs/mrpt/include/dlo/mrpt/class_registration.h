/// \file class_registration.h
/// \brief Registration of DLO's MRPT classes with MRPT's RTTI, for creation by class name.
#pragma once

namespace dlo {

/// Registers mrpt::slam::CDirectHeightAligner with MRPT's class factory. dlo_mrpt also does this
/// when it is loaded, but a static library's object files are only linked when referenced, so a
/// program that only ever names the class as a string must call this once. Idempotent.
void registerMrptClasses();

}  // namespace dlo
