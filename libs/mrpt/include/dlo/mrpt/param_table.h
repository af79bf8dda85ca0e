/// \file param_table.h
/// \brief A parameter struct <-> MRPT INI mapping: one table of (section, key, doc, field) per
/// struct, and the loading, overriding, saving and dumping every program shares.
///
/// Each parameter has exactly one INI key, named like its field, in the section of its group.
/// Missing keys keep their current value; unknown keys in a known section are rejected (a typo
/// would otherwise silently leave the default in force); every loader validates the result and
/// throws dlo::InputError with one sentence naming the key.
#pragma once

#include <mrpt/config/CConfigFileBase.h>
#include <algorithm>
#include <functional>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace dlo {

/// A value of a parameter that takes one of a few named values (an enum, a boolean), as the
/// INI file spells it and as the field stores it.
struct NamedValue {
  std::string name;
  double value;
};

/// The names of a boolean parameter: false and true.
inline std::vector<NamedValue> booleanNames() {
  return {{"false", 0.0}, {"true", 1.0}};
}

/// One INI key of the parameter struct P. Numbers travel as doubles (integers exact up to
/// 2^53); a field with `names` is written and read by those names only.
template <typename P>
struct ParamField {
  std::string section;
  std::string key;
  std::string doc;
  bool is_int = false;
  std::function<double(const P&)> get;
  std::function<void(P&, double)> set;
  std::vector<NamedValue> names;  ///< empty: a number

  std::string name() const { return section + "." + key; }
};

/// The field `member` of the group `group` of P, e.g. paramField("grid", "cols", &DloParams::grid,
/// &HeightGridParams::cols, "cells along x").
/// Booleans and enums need `names` (for a bool, booleanNames()); ints may have them
/// (solver.dof: "3" or "6").
template <typename P, typename G, typename T>
ParamField<P> paramField(const char* section, const char* key, G P::*group, T G::*member,
                         const char* doc, std::vector<NamedValue> names = {}) {
  static_assert(std::is_same_v<T, int> || std::is_same_v<T, double> || std::is_same_v<T, bool> ||
                    std::is_enum_v<T>,
                "int, double, bool or enum parameters");
  if constexpr (std::is_same_v<T, bool> || std::is_enum_v<T>) {
    if (names.empty()) throw std::logic_error(std::string("paramField: ") + key + " needs names");
  }
  return ParamField<P>{
      section,
      key,
      doc,
      !std::is_same_v<T, double>,
      [group, member](const P& p) { return static_cast<double>((p.*group).*member); },
      [group, member](P& p, double v) {
        if constexpr (std::is_same_v<T, bool>) {
          (p.*group).*member = v != 0.0;
        } else if constexpr (std::is_enum_v<T>) {
          (p.*group).*member = static_cast<T>(static_cast<int>(v));
        } else {
          (p.*group).*member = static_cast<T>(v);
        }
      },
      std::move(names)};
}

/// A field of an inner struct I, reached through the member `inner` of P.
template <typename P, typename I>
ParamField<P> liftField(const ParamField<I>& f, I P::*inner) {
  return ParamField<P>{f.section,
                       f.key,
                       f.doc,
                       f.is_int,
                       [g = f.get, inner](const P& p) { return g(p.*inner); },
                       [s = f.set, inner](P& p, double v) { s(p.*inner, v); },
                       f.names};
}

/// Helpers of ParamTable that do not depend on P.
namespace param_text {
/// "prefix.section", or `section` when prefix is empty.
std::string sectionName(const std::string& prefix, const std::string& section);
std::string trim(const std::string& s);
/// Parses `text` as an integer or a number. \throws InputError naming `name` and `where`.
double parse(const std::string& text, bool is_int, const std::string& name,
             const std::string& where);
/// Parses `text` as one of `names`. \throws InputError naming `name`, `where` and the names
/// accepted; for a number that was the value's old spelling, also the name to write instead.
double parseNamed(const std::string& text, const std::vector<NamedValue>& names,
                  const std::string& name, const std::string& where);
/// Shortest decimal text that reads back to exactly `x`.
std::string exact(double x, bool is_int);
/// The name of `x` among `names`, or exact(x, true) if it has none.
std::string named(double x, const std::vector<NamedValue>& names);
/// "a, b or c".
std::string nameList(const std::vector<NamedValue>& names);
/// `text` as INI comment lines ("; " and at most 100 characters each, words kept whole).
std::string comment(const std::string& text);
/// Throws InputError(problem) if problem is not empty.
void throwIfProblem(const std::string& problem);
/// Throws InputError(problem).
[[noreturn]] void fail(const std::string& problem);
/// Throws InputError naming `path` if it cannot be opened.
void requireReadableConfig(const std::string& path);
/// Throws an InputError of `e`'s message (one line, see oneLineMessage()) with
/// "config file 'path': " in front.
[[noreturn]] void rethrowWithFile(const std::string& path, const std::exception& e);
}  // namespace param_text

/// The INI mapping of parameter struct P.
template <typename P>
class ParamTable {
 public:
  ParamTable(std::vector<ParamField<P>> fields, std::function<std::string(const P&)> validate)
      : fields_(std::move(fields)), validate_(std::move(validate)) {}

  const std::vector<ParamField<P>>& fields() const { return fields_; }

  /// The value of `f` in `params` as the INI file spells it.
  static std::string text(const ParamField<P>& f, const P& params) {
    return f.names.empty() ? param_text::exact(f.get(params), f.is_int)
                           : param_text::named(f.get(params), f.names);
  }

  /// Reads P from `config` starting from `defaults`; sections named prefix.section.
  P load(const mrpt::config::CConfigFileBase& config, const std::string& prefix,
         const P& defaults) const {
    P p = defaults;
    for (const std::string& section : sections()) {
      const std::string name = param_text::sectionName(prefix, section);
      if (!config.sectionExists(name)) continue;
      std::vector<std::string> keys;
      config.getAllKeys(name, keys);
      for (const std::string& key : keys) {
        const ParamField<P>* f = find(section, key);
        if (!f) unknown(section + "." + key, "in section [" + name + "]");
        f->set(p, read(*f, config.read_string(name, key, "", true), "in section [" + name + "]"));
      }
    }
    param_text::throwIfProblem(validate_(p));
    return p;
  }

  /// Like load() on the INI file `path`; errors name the file.
  P loadFile(const std::string& path, const std::string& prefix, const P& defaults) const;

  /// Applies "section.key=value" assignments in order, then validates.
  void applyOverrides(P& params, const std::vector<std::string>& assignments) const {
    P p = params;
    for (const std::string& a : assignments) {
      const auto eq = a.find('=');
      const auto dot = a.find('.');
      if (eq == std::string::npos || dot == std::string::npos || dot > eq) {
        param_text::fail("override '" + a + "' is not of the form section.key=value.");
      }
      const std::string section = param_text::trim(a.substr(0, dot));
      const std::string key = param_text::trim(a.substr(dot + 1, eq - dot - 1));
      const ParamField<P>* f = find(section, key);
      if (!f) unknown(section + "." + key, "in override '" + a + "'");
      f->set(p, read(*f, a.substr(eq + 1), "override '" + a + "'"));
    }
    param_text::throwIfProblem(validate_(p));
    params = p;
  }

  /// Writes every parameter to `config`.
  void save(const P& params, mrpt::config::CConfigFileBase& config,
            const std::string& prefix) const {
    for (const ParamField<P>& f : fields_) {
      config.write(param_text::sectionName(prefix, f.section), f.key, text(f, params));
    }
  }

  /// Commented INI text; load() of it gives back `params` exactly.
  std::string toIni(const P& params, const std::string& prefix) const {
    return toIni(params, prefix, {}, "");
  }

  /// Commented INI text as a shipped config file has it: every key's doc wrapped as "; "
  /// comment lines, then the key; the keys named in `commented_out` ("section.key") are
  /// written commented out (";key = value") with `commented_note` appended to their doc.
  std::string toIni(const P& params, const std::string& prefix,
                    const std::vector<std::string>& commented_out,
                    const std::string& commented_note) const {
    std::string out, current;
    for (const ParamField<P>& f : fields_) {
      if (current != f.section) {
        if (!current.empty()) out += "\n";
        current = f.section;
        out += "[" + param_text::sectionName(prefix, f.section) + "]\n";
      }
      const bool off =
          std::find(commented_out.begin(), commented_out.end(), f.name()) != commented_out.end();
      out += param_text::comment(off ? f.doc + " " + commented_note : f.doc);
      out += (off ? ";" : "") + f.key + " = " + text(f, params) + "\n";
    }
    return out;
  }

 private:
  static double read(const ParamField<P>& f, const std::string& value, const std::string& where) {
    return f.names.empty() ? param_text::parse(value, f.is_int, f.name(), where)
                           : param_text::parseNamed(value, f.names, f.name(), where);
  }
  std::vector<std::string> sections() const {
    std::vector<std::string> out;
    for (const ParamField<P>& f : fields_)
      if (out.empty() || out.back() != f.section) out.push_back(f.section);
    return out;
  }
  const ParamField<P>* find(const std::string& section, const std::string& key) const {
    for (const ParamField<P>& f : fields_)
      if (f.section == section && f.key == key) return &f;
    return nullptr;
  }
  [[noreturn]] void unknown(const std::string& name, const std::string& where) const {
    std::string keys;
    for (const ParamField<P>& f : fields_) keys += (keys.empty() ? "" : ", ") + f.name();
    param_text::fail("unknown parameter " + name + " " + where + ": expected one of " + keys + ".");
  }

  std::vector<ParamField<P>> fields_;
  std::function<std::string(const P&)> validate_;
};

}  // namespace dlo

#include "dlo/mrpt/param_table_impl.h"
