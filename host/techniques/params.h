// Technique parameters: each technique declares its parameters (name, default, range, help) so the CLI
// can offer them as options and the EXR header can record them, without the library knowing about CLI11.
#pragma once

#include <map>
#include <string>
#include <vector>

namespace penumbra {

struct ParamSpec {
  std::string name;     // option name without dashes, e.g. "pcf-radius"
  double defaultValue;  // numeric parameters only; choices are encoded as indices into `choices`
  double min, max;      // inclusive valid range
  std::string help;
  std::vector<std::string> choices = {};  // non-empty: a named choice ("uniform", "adaptive")
  bool text = false;                      // a free-form text value (a list such as "0.2,0.5"), see textParam
  std::string textDefault = {};
  // Numeric parameters: this word sets autoValue, outside [min, max], for a value chosen per frame (map-size's 0,
  // blur-radius's -1); a default of autoValue is the word's.
  std::string autoName = {};
  double autoValue = 0.0;
  bool isAuto(double value) const { return !autoName.empty() && value == autoValue; }
};

// A text parameter: stored verbatim, validated by the technique that reads it (Params::getText).
ParamSpec textParam(std::string name, std::string help, std::string defaultText = {});

// The spec named `name` in `specs`, to change a shared parameter's default or help for one technique; throws
// std::out_of_range when there is none.
ParamSpec& paramNamed(std::vector<ParamSpec>& specs, const std::string& name);

// Values by name, validated against their specs.
class Params {
 public:
  Params() = default;
  explicit Params(const std::vector<ParamSpec>& specs);  // every parameter at its default

  // Sets a value from text ("0.002", or a choice name). Throws std::invalid_argument naming the parameter,
  // the value and the valid range/choices.
  void set(const std::string& name, const std::string& text);
  double get(const std::string& name) const;  // throws std::out_of_range for an undeclared name
  bool has(const std::string& name) const { return values_.count(name) != 0 || texts_.count(name) != 0; }
  int getInt(const std::string& name) const { return static_cast<int>(get(name)); }
  // Whether `name` holds its spec's auto value (ParamSpec::isAuto); false for an undeclared name.
  bool isAuto(const std::string& name) const;
  const std::string& getText(const std::string& name) const;  // a text parameter's value
  std::string describe() const;                               // "bias=0.002 pcf-radius=2", for provenance

 private:
  std::vector<ParamSpec> specs_;
  std::map<std::string, double> values_;
  std::map<std::string, std::string> texts_;
};

}  // namespace penumbra
