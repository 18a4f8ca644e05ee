/* SPDX-License-Identifier: MIT */
/* cli.h: the `sablier` command line (app/cli/sablier.c), checked without running anything. */
#ifndef APP_CLI_H
#define APP_CLI_H

/// `sablier ARGV...` (argv[0] "sablier", argv[1] the command) checked as the command checks it
/// before doing anything: 0 when the command line is good (or asks for --help or --version), else
/// the exit status of the usage error (message on stderr). Reads no file, writes nothing, starts
/// no run, process or thread; for tests/fuzz/fuzz_cli.c.
int sablier_parse_arguments(int argc, char **argv);

#endif
