"""The CLI lists only command groups with real functionality behind them,
and every listed group explains itself with --help."""
import re

from sftest import binary, check, run

# Groups the CLI may show and the module each needs. A group must be listed
# exactly when its module is built into the binary.
KNOWN = ["ecat", "opcua", "agent", "cnp", "kb", "cloud", "history", "demo"]

top = run([binary(), "--help"]).stdout
check("smartfactory" in top and "--version" in top, "top-level --help describes the program")
listed = re.findall(r"^\s{2}(\w+)\s", top.split("Subcommands:")[1], re.M) if "Subcommands:" in top else []
check(all(g in KNOWN for g in listed), f"only known groups are listed: {listed}")
check("ecat" in listed, "the ecat group is listed (EtherCAT module is built)")
for group in listed:
    text = run([binary(), group, "--help"]).stdout
    subs = re.findall(r"^\s{2}(\w+)\s", text.split("Subcommands:")[1], re.M) if "Subcommands:" in text else []
    check(len(subs) > 0, f"group '{group}' has subcommands: {subs}")
    for sub in subs:
        sub_help = run([binary(), group, sub, "--help"]).stdout
        check("Options:" in sub_help and len(sub_help.splitlines()) > 3, f"'{group} {sub} --help' explains its options")
version = run([binary(), "--version"]).stdout
check(re.match(r"smartfactory \d+\.\d+\.\d+", version) is not None, f"--version prints the version: {version.strip()}")
bad = run([binary(), "--log-level", "loud"], check_rc=False)
check(bad.returncode != 0 and "loud" in (bad.stderr + bad.stdout), "an unknown log level is refused with a message")
