#include "dlo/mrpt/dlo_config.h"

#include <mrpt/config/CConfigFile.h>
#include <cerrno>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <limits>
#include <sstream>
#include <type_traits>

#include "dlo/mrpt/input_error.h"

namespace dlo {

namespace {

/// One INI key: where it lives, its documentation, and how to reach the field. The table below is
/// the single place that maps DloParams to INI; the doc strings repeat the headers' comments.
struct Field {
  const char* section;
  const char* key;
  const char* doc;
  bool is_int;
  std::function<double(const DloParams&)> get;  ///< integers are exact in a double
  std::function<void(DloParams&, double)> set;

  std::string name() const { return std::string(section) + "." + key; }
};

template <typename Group, typename T>
Field field(const char* section, const char* key, Group DloParams::*group, T Group::*member,
            const char* doc) {
  static_assert(std::is_same_v<T, int> || std::is_same_v<T, double>,
                "DloParams fields are int or double");
  return Field{section,
               key,
               doc,
               std::is_same_v<T, int>,
               [group, member](const DloParams& p) { return double((p.*group).*member); },
               [group, member](DloParams& p, double v) { (p.*group).*member = static_cast<T>(v); }};
}

const std::vector<Field>& fields() {
  using D = DloParams;
  using G = HeightGridParams;
  using S = SelectionParams;
  using V = SolverParams;
  static const std::vector<Field> table = {
      field("grid", "cols", &D::grid, &G::cols, "cells along x (paper: 400)"),
      field("grid", "rows", &D::grid, &G::rows, "cells along y (paper: 400)"),
      field("grid", "resolution", &D::grid, &G::resolution,
            "metres per cell at the finest level (paper: 0.10)"),
      field("grid", "min_points", &D::grid, &G::min_points,
            "a cell needs at least this many points to be valid (paper: 3)"),
      field("grid", "min_z", &D::grid, &G::min_z,
            "points below this height (m, grid frame) are ignored"),
      field("grid", "max_z", &D::grid, &G::max_z,
            "points above this height (m, grid frame) are ignored"),
      field("grid", "levels", &D::grid, &G::levels,
            "pyramid levels; level k has cells 2^k times larger"),
      field("selection", "min_gradient", &D::selection, &S::min_gradient,
            "|grad H| threshold, metres of height per metre"),
      field("selection", "block_size", &D::selection, &S::block_size,
            "at most one gradient cell per block x block cells (even coverage)"),
      field("selection", "max_cells", &D::selection, &S::max_cells,
            "cap on gradient cells per level; thinned evenly beyond it"),
      field("selection", "ground_stride", &D::selection, &S::ground_stride,
            "6-DoF only: also take every n-th valid cell (any gradient) to observe z, roll and "
            "pitch from the ground; 0 disables"),
      field("solver", "dof", &D::solver, &V::dof,
            "3 (x, y, yaw) or 6 (full SE(3), z, roll and pitch observed from the ground)"),
      field("solver", "max_iterations", &D::solver, &V::max_iterations, "per pyramid level"),
      field("solver", "huber_delta", &D::solver, &V::huber_delta,
            "robust kernel width on the height error, metres"),
      field("solver", "max_residual", &D::solver, &V::max_residual,
            "residuals beyond this (m) are outliers, weight 0"),
      field("solver", "min_step_translation", &D::solver, &V::min_step_translation,
            "convergence: translation update below this (m)"),
      field("solver", "min_step_rotation", &D::solver, &V::min_step_rotation,
            "convergence: rotation update below this (rad)"),
      field("solver", "min_cells", &D::solver, &V::min_cells,
            "fewer usable cells than this: degenerate"),
      field("solver", "degeneracy_eigen_ratio", &D::solver, &V::degeneracy_eigen_ratio,
            "eig_min/eig_max of the scaled Hessian below this: degenerate"),
      field("solver", "rotation_scale", &D::solver, &V::rotation_scale,
            "metres; scales rotations against translations when judging conditioning"),
  };
  return table;
}

const char* const kGroups[] = {"grid", "selection", "solver"};

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return {};
  const auto e = s.find_last_not_of(" \t\r\n");
  return s.substr(b, e - b + 1);
}

std::string keyList() {
  std::string out;
  for (const Field& f : fields()) out += (out.empty() ? "" : ", ") + f.name();
  return out;
}

const Field* findField(const std::string& section, const std::string& key) {
  for (const Field& f : fields())
    if (section == f.section && key == f.key) return &f;
  return nullptr;
}

/// Parses `text` into the field; `where` says where the value came from, for the message.
void assign(const Field& f, const std::string& text, const std::string& where, DloParams& p) {
  const std::string v = trim(text);
  const char* begin = v.c_str();
  char* end = nullptr;
  errno = 0;
  if (f.is_int) {
    const long long x = std::strtoll(begin, &end, 10);
    if (v.empty() || *end != '\0' || errno == ERANGE || x < std::numeric_limits<int>::min() ||
        x > std::numeric_limits<int>::max()) {
      throw InputError("parameter " + f.name() + " = '" + v + "' (" + where +
                       ") is not an integer.");
    }
    f.set(p, static_cast<double>(x));
  } else {
    const double x = std::strtod(begin, &end);
    if (v.empty() || *end != '\0' || errno == ERANGE) {
      throw InputError("parameter " + f.name() + " = '" + v + "' (" + where + ") is not a number.");
    }
    f.set(p, x);
  }
}

void validateOrThrow(const DloParams& p) {
  const std::string problem = p.validate();
  if (!problem.empty()) throw InputError(problem);
}

/// Shortest decimal text that reads back to exactly `x`, so a dump round-trips without
/// printing 0.1 as 0.10000000000000001.
std::string exactText(double x) {
  for (int precision = 6; precision <= 17; ++precision) {
    std::ostringstream s;
    s.precision(precision);
    s << x;
    if (std::strtod(s.str().c_str(), nullptr) == x) return s.str();
  }
  std::ostringstream s;
  s.precision(17);
  s << x;
  return s.str();
}

std::string valueText(const Field& f, const DloParams& p) {
  return f.is_int ? std::to_string(static_cast<int>(f.get(p))) : exactText(f.get(p));
}

}  // namespace

std::string dloSectionName(const std::string& prefix, const std::string& group) {
  return prefix.empty() ? group : prefix + "." + group;
}

DloParams loadDloParams(const mrpt::config::CConfigFileBase& config, const std::string& prefix,
                        const DloParams& defaults) {
  DloParams p = defaults;
  for (const char* group : kGroups) {
    const std::string section = dloSectionName(prefix, group);
    if (!config.sectionExists(section)) continue;
    std::vector<std::string> keys;
    config.getAllKeys(section, keys);
    for (const std::string& key : keys) {
      const Field* f = findField(group, key);
      if (!f) {
        // A typo would otherwise silently leave the default in force.
        throw InputError("unknown parameter " + std::string(group) + "." + key + " in section [" +
                         section + "]: expected one of " + keyList() + ".");
      }
      assign(*f, config.read_string(section, key, "", true), "in section [" + section + "]", p);
    }
  }
  validateOrThrow(p);
  return p;
}

DloParams loadDloParamsFile(const std::string& path, const std::string& prefix,
                            const DloParams& defaults) {
  if (!std::ifstream(path)) {
    throw InputError("cannot open config file '" + path + "': no such file or not readable.");
  }
  mrpt::config::CConfigFile config(path);
  try {
    return loadDloParams(config, prefix, defaults);
  } catch (const InputError& e) {
    throw InputError("config file '" + path + "': " + e.what());
  }
}

void applyDloParamOverrides(DloParams& params, const std::vector<std::string>& assignments) {
  DloParams p = params;
  for (const std::string& a : assignments) {
    const auto eq = a.find('=');
    const auto dot = a.find('.');
    if (eq == std::string::npos || dot == std::string::npos || dot > eq) {
      throw InputError("override '" + a + "' is not of the form section.key=value.");
    }
    const std::string section = trim(a.substr(0, dot));
    const std::string key = trim(a.substr(dot + 1, eq - dot - 1));
    const Field* f = findField(section, key);
    if (!f) {
      throw InputError("unknown parameter " + section + "." + key + " in override '" + a +
                       "': expected one of " + keyList() + ".");
    }
    assign(*f, a.substr(eq + 1), "override '" + a + "'", p);
  }
  validateOrThrow(p);
  params = p;
}

void saveDloParams(const DloParams& params, mrpt::config::CConfigFileBase& config,
                   const std::string& prefix) {
  for (const Field& f : fields())
    config.write(dloSectionName(prefix, f.section), f.key, valueText(f, params));
}

std::string dloParamsToIni(const DloParams& params, const std::string& prefix) {
  std::ostringstream out;
  std::string current;
  for (const Field& f : fields()) {
    if (current != f.section) {
      if (!current.empty()) out << "\n";
      current = f.section;
      out << "[" << dloSectionName(prefix, f.section) << "]\n";
    }
    out << "; " << f.doc << "\n" << f.key << " = " << valueText(f, params) << "\n";
  }
  return out.str();
}

}  // namespace dlo
