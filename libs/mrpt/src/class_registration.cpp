#include "dlo/mrpt/class_registration.h"

#include <mrpt/rtti/CObject.h>

#include "dlo/mrpt/CDirectHeightAligner.h"

namespace dlo {

void registerMrptClasses() {
  mrpt::rtti::registerClass(CLASS_ID(mrpt::slam::CDirectHeightAligner));
}

}  // namespace dlo
