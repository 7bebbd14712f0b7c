#include "help_format.h"

#include <cstdio>
#include <memory>
#include <sstream>
#include <vector>

namespace hapstate {
namespace {

class HelpFormatter : public CLI::Formatter {
 public:
  HelpFormatter() { column_width(34); }

  // " INT", " TEXT REQUIRED", " surface|all": the type without the validators' descriptions.
  std::string make_option_opts(const CLI::Option* opt) const override {
    if (opt->get_type_size() == 0) return "";
    std::string out = " ";
    if (!opt->get_option_text().empty()) {
      out += opt->get_option_text();
    } else {
      const std::string type = opt->get_type_name();
      out += type.substr(0, type.find(':'));
    }
    if (opt->get_expected_max() == CLI::detail::expected_max_vector_size)
      out += " ...";
    else if (opt->get_expected_min() > 1)
      out += " x " + std::to_string(opt->get_expected());
    if (opt->get_required()) out += " REQUIRED";
    return out;
  }

  std::string make_option_desc(const CLI::Option* opt) const override {
    std::string desc = opt->get_description();
    const std::string value = opt->get_default_str();
    if (opt->get_type_size() != 0 && !opt->get_required() && !value.empty() && value != "[]" &&
        desc.find("default") == std::string::npos)
      desc += " (default " + value + ")";
    return desc;
  }
};

}  // namespace

void use_hapstate_help(CLI::App& app, bool help_all) {
  app.formatter(std::make_shared<HelpFormatter>());
  app.option_defaults()->always_capture_default();
  if (help_all) {
    app.set_help_flag();
    app.set_help_all_flag("-h,--help",
                          "Print this help message (with every subcommand's options) "
                          "and exit");
  }
}

namespace {

// A validator accepting numbers for which ok(x) holds; its error says "must be <what>".
CLI::Validator number_check(const std::string& what, bool (*ok)(double, double, double), double lo,
                            double hi) {
  return CLI::Validator(
      [what, ok, lo, hi](std::string& text) -> std::string {
        double x = 0;
        if (!CLI::detail::lexical_cast(text, x)) return "must be a number, not '" + text + "'";
        return ok(x, lo, hi) ? std::string() : "must be " + what + ", not " + text;
      },
      "");
}

std::string number_text(double x) {
  std::ostringstream s;
  s << x;
  return s.str();
}

}  // namespace

int exit_after_parse_error(CLI::App& app, const CLI::ParseError& error, const char* program) {
  const std::vector<std::string> rest = app.remaining();
  if (dynamic_cast<const CLI::RequiredError*>(&error) != nullptr && !rest.empty() &&
      app.get_require_subcommand_min() > 0 && app.get_subcommands().empty()) {
    std::string names;
    for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; }))
      names += (names.empty() ? "" : ", ") + sub->get_name();
    std::fprintf(stderr,
                 "%s: error: unknown subcommand '%s' (one of: %s)\nRun with --help for "
                 "more information.\n",
                 program, rest.front().c_str(), names.c_str());
    return 2;
  }
  return app.exit(error) == 0 ? 0 : 2;
}

CLI::Validator positive() {
  return number_check(
      "> 0", [](double x, double, double) { return x > 0; }, 0, 0);
}

CLI::Validator non_negative() {
  return number_check(
      ">= 0", [](double x, double, double) { return x >= 0; }, 0, 0);
}

CLI::Validator in_range(double lo, double hi) {
  return number_check(
      "in [" + number_text(lo) + ", " + number_text(hi) + "]",
      [](double x, double l, double h) { return x >= l && x <= h; }, lo, hi);
}

std::string choices(std::initializer_list<const char*> names) {
  std::string out;
  for (const char* name : names) out += (out.empty() ? "" : "|") + std::string(name);
  return out;
}

}  // namespace hapstate
