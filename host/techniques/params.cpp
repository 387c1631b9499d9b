// Parameter parsing and validation.
#include "host/techniques/params.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace penumbra {

ParamSpec textParam(std::string name, std::string help, std::string defaultText) {
  ParamSpec spec{std::move(name), 0, 0, 0, std::move(help)};
  spec.text = true;
  spec.textDefault = std::move(defaultText);
  return spec;
}

ParamSpec& paramNamed(std::vector<ParamSpec>& specs, const std::string& name) {
  for (ParamSpec& spec : specs)
    if (spec.name == name) return spec;
  throw std::out_of_range("no parameter --" + name);
}

Params::Params(const std::vector<ParamSpec>& specs) : specs_(specs) {
  for (const ParamSpec& spec : specs_) {
    values_[spec.name] = spec.defaultValue;
    if (spec.text) texts_[spec.name] = spec.textDefault;
  }
}

void Params::set(const std::string& name, const std::string& text) {
  auto spec = std::find_if(specs_.begin(), specs_.end(), [&](const ParamSpec& s) { return s.name == name; });
  if (spec == specs_.end()) throw std::invalid_argument(fmt::format("unknown parameter '{}'", name));
  if (spec->text) {
    texts_[name] = text;
    return;
  }
  if (!spec->choices.empty()) {
    auto choice = std::find(spec->choices.begin(), spec->choices.end(), text);
    if (choice == spec->choices.end())
      throw std::invalid_argument(
          fmt::format("--{}: '{}' is not one of {}", name, text, fmt::join(spec->choices, ", ")));
    values_[name] = static_cast<double>(choice - spec->choices.begin());
    return;
  }
  if (!spec->autoName.empty() && text == spec->autoName) {
    values_[name] = spec->autoValue;
    return;
  }
  size_t used = 0;
  double value = 0;
  try {
    value = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != text.size() || !std::isfinite(value))
    throw std::invalid_argument(fmt::format("--{}: '{}' is not a finite number", name, text));
  if (value < spec->min || value > spec->max)
    throw std::invalid_argument(fmt::format("--{}: {} is outside [{}, {}]", name, text, spec->min, spec->max));
  values_[name] = value;
}

bool Params::isAuto(const std::string& name) const {
  auto spec = std::find_if(specs_.begin(), specs_.end(), [&](const ParamSpec& s) { return s.name == name; });
  return spec != specs_.end() && !spec->text && spec->isAuto(values_.at(name));
}

double Params::get(const std::string& name) const {
  auto it = values_.find(name);
  if (it == values_.end()) throw std::out_of_range(fmt::format("parameter '{}' is not declared", name));
  return it->second;
}

const std::string& Params::getText(const std::string& name) const {
  auto it = texts_.find(name);
  if (it == texts_.end()) throw std::out_of_range(fmt::format("text parameter '{}' is not declared", name));
  return it->second;
}

std::string Params::describe() const {
  std::string text;
  for (const ParamSpec& spec : specs_) {
    if (!text.empty()) text += ' ';
    const double value = values_.at(spec.name);
    if (spec.text) {
      text += fmt::format("{}={}", spec.name, texts_.at(spec.name));
      continue;
    }
    if (spec.isAuto(value))
      text += fmt::format("{}={}", spec.name, spec.autoName);
    else
      text += spec.choices.empty() ? fmt::format("{}={}", spec.name, value)
                                   : fmt::format("{}={}", spec.name, spec.choices.at(static_cast<size_t>(value)));
  }
  return text;
}

}  // namespace penumbra
