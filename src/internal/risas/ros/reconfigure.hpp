// dynamic_reconfigure for risas/RisasNodelet: one server per section of
// RisasParams, on the section's namespace (~detector, ~descriptor, ~match), so
// a reconfiguration sets the very names the parameter files set
// (~detector/tau). A .cfg field stands for the params_fields.hpp field of the
// same name in its section; there is no second list. Tests hold the .cfg
// names and ranges equal to params_fields.hpp.
#pragma once

#include "risas/params_fields.hpp"

#include <dynamic_reconfigure/config_tools.h>

#include <boost/any.hpp>

#include <string>

namespace risas_ros {

namespace detail {

// Assigns a .cfg value (int, double or bool) to a params field of any number type.
template <class T>
void assignFromAny(T& field, const boost::any& value) {
  if (const int* i = boost::any_cast<int>(&value)) field = static_cast<T>(*i);
  if (const double* d = boost::any_cast<double>(&value)) field = static_cast<T>(*d);
  if (const bool* b = boost::any_cast<bool>(&value)) field = static_cast<T>(*b);
}

// Calls f(field) for the field of `section` named `name`, if there is one.
template <class Section, class F>
void withField(Section& section, const std::string& name, F&& f) {
  risas::visitFields(section, [&](const char* field_name, auto& field, auto...) {
    if (name == field_name) f(field);
  });
}

}  // namespace detail

// The .cfg's Config holding `section`'s values; its fields without a
// namesake in the section (none, by the tests) keep the .cfg defaults.
template <class Config, class Section>
Config toConfig(Section section) {
  dynamic_reconfigure::Config message;
  for (const auto& description : Config::__getParamDescriptions__()) {
    detail::withField(section, description->name, [&](const auto& field) {
      using dynamic_reconfigure::ConfigTools;
      if (description->type == "int") ConfigTools::appendParameter(message, description->name, static_cast<int>(field));
      if (description->type == "double") ConfigTools::appendParameter(message, description->name, static_cast<double>(field));
      if (description->type == "bool") ConfigTools::appendParameter(message, description->name, static_cast<bool>(field));
    });
  }
  Config config = Config::__getDefault__();
  config.__fromMessage__(message);
  return config;
}

// `section` with the Config's values in the fields it stands for.
template <class Config, class Section>
Section applyConfig(const Config& config, Section section) {
  for (const auto& description : Config::__getParamDescriptions__()) {
    boost::any value;
    description->getValue(config, value);
    detail::withField(section, description->name, [&](auto& field) { detail::assignFromAny(field, value); });
  }
  return section;
}

}  // namespace risas_ros
