#include "dlo/bench/method_registry.h"

#include <cstdio>

#include "dlo/bench/dlo_methods.h"
#include "dlo/bench/icp_method.h"
#ifdef DLO_HAVE_PCL
#include "dlo/bench/pcl_methods.h"
#endif

namespace dlo::bench {

namespace {

std::string describeDlo(const SlamParams& p, const std::string& reference) {
  char text[160];
  std::snprintf(text, sizeof text, "deskew; %dx%d grid of %.2f m, %d levels, %d-DoF; %s",
                p.registration.grid.cols, p.registration.grid.rows, p.registration.grid.resolution,
                p.registration.grid.levels, p.registration.solver.dof, reference.c_str());
  return text;
}

std::vector<MethodSpec> makeMethods() {
  std::vector<MethodSpec> methods;
  const SlamParams paper = DloFrameToFrame::paperParams(SlamParams());
  methods.push_back({"dlo-paper", describeDlo(paper, "previous scan, no loop closure"), false,
                     [] { return std::make_unique<DloFrameToFrame>(); }});
  const SlamParams full;
  char reference[96];
  std::snprintf(reference, sizeof reference,
                "local map of up to %d keyframes within %g m, loop closure",
                full.odometry.local_map_keyframes, full.odometry.local_map_extent);
  methods.push_back(
      {"dlo", describeDlo(full, reference), false, [] { return std::make_unique<DloPipeline>(); }});
  methods.push_back({"icp",
                     IcpFrameToFrame::describe(ClassicPreprocessing(), benchmarkIcpOptions()), true,
                     [] { return std::make_unique<IcpFrameToFrame>(); }});
#ifdef DLO_HAVE_PCL
  for (MethodSpec& m : pclMethods()) methods.push_back(std::move(m));
#endif
  return methods;
}

}  // namespace

const std::vector<MethodSpec>& availableMethods() {
  static const std::vector<MethodSpec> methods = makeMethods();
  return methods;
}

const MethodSpec* findMethod(const std::string& name) {
  for (const MethodSpec& m : availableMethods()) {
    if (m.name == name) return &m;
  }
  return nullptr;
}

std::string availableMethodNames() {
  std::string names;
  for (const MethodSpec& m : availableMethods()) names += (names.empty() ? "" : ",") + m.name;
  return names;
}

}  // namespace dlo::bench
