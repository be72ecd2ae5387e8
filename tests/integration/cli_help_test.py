"""The CLI lists only command groups with real functionality behind them,
and every listed group explains itself with --help."""
import re

from sftest import binary, check, run

# Groups the CLI may show and the module each needs. A group must be listed
# exactly when its module is built into the binary.
KNOWN = ["ecat", "opcua", "agent", "cnp", "kb", "cloud", "history", "plant", "demo", "gateway", "machine",
         "orders", "order", "simulate", "line"]

def subcommands(help_text):
    """The names in the Subcommands: section (it ends at the first blank line)."""
    if "Subcommands:" not in help_text:
        return []
    section = help_text.split("Subcommands:")[1].split("\n\n")[0]
    return re.findall(r"^\s{2}(\w+)\s", section, re.M)


def explains_options(help_text):
    return "Options:" in help_text and len(help_text.splitlines()) > 3


top = run([binary(), "--help"]).stdout
check("smartfactory" in top and "--version" in top, "top-level --help describes the program")
listed = subcommands(top)
check(all(g in KNOWN for g in listed), f"only known groups are listed: {listed}")
check("ecat" in listed, "the ecat group is listed (EtherCAT module is built)")
for group in listed:
    text = run([binary(), group, "--help"]).stdout
    subs = subcommands(text)
    # A group has subcommands; a command on its own (cloud, demo) explains its options.
    check(len(subs) > 0 or explains_options(text), f"'{group}' has subcommands {subs} or explains its options")
    for sub in subs:
        sub_help = run([binary(), group, sub, "--help"]).stdout
        check(explains_options(sub_help), f"'{group} {sub} --help' explains its options")
        # One level deeper (e.g. `ecat sdo list|read|write`).
        for leaf in subcommands(sub_help):
            leaf_help = run([binary(), group, sub, leaf, "--help"]).stdout
            check(explains_options(leaf_help), f"'{group} {sub} {leaf} --help' explains its options")
version = run([binary(), "--version"]).stdout
check(re.match(r"smartfactory \d+\.\d+\.\d+", version) is not None, f"--version prints the version: {version.strip()}")
bad = run([binary(), "--log-level", "loud"], check_rc=False)
check(bad.returncode != 0 and "loud" in (bad.stderr + bad.stdout), "an unknown log level is refused with a message")
