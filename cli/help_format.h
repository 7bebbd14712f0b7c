// The command-line conventions every hapstate executable shares (CLI11): a help text that shows
// each option's value type and default and none of the parser's internals (validator ranges,
// enum maps), and a --help that includes the subcommands' options.
#pragma once

#include <CLI/CLI.hpp>

#include <initializer_list>
#include <string>

namespace hapstate {

// Call right after constructing `app`, before adding options: defaults are captured from the
// bound variables, and options whose description does not say "default" get "(default X)".
// With `help_all`, --help shows every subcommand's options too.
void use_hapstate_help(CLI::App& app, bool help_all = false);

// After a failed app.parse(): prints the error (an unknown subcommand is named, with the
// subcommands there are) and returns the exit code (0 for --help, 2 otherwise).
int exit_after_parse_error(CLI::App& app, const CLI::ParseError& error, const char* program);

// Checks with readable messages ("must be > 0, not -1"; CLI11's own print their range up to
// the largest double).
CLI::Validator positive();
CLI::Validator non_negative();
CLI::Validator in_range(double lo, double hi);

// The value text of an option with named choices, "surface|all": for options whose parser
// (a CLI::CheckedTransformer) would otherwise show its internal map.
std::string choices(std::initializer_list<const char*> names);

}  // namespace hapstate
