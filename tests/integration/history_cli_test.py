"""`smartfactory history` end to end on a SQLite store: write samples, list
the registry, query raw and aggregated (text and --json), retention, and
clear errors (exit code 2 for bad input, 1 for an unreachable database)."""
import atexit
import os
import shutil
import tempfile

from sftest import binary, check, run, run_json

tmp = tempfile.mkdtemp(prefix="sf-history-cli-")
atexit.register(shutil.rmtree, tmp, True)
db = "sqlite:" + os.path.join(tmp, "history.db")
series = ["--server", "opc.tcp://oven:4840", "--node", "ns=2;s=Temp", "--path", "/Objects/Oven/Temp", "--unit", "degC"]

for i in range(10):
    status = ["--status", str(0x80000000)] if i == 3 else []
    run([binary(), "history", "write", "--db", db, *series, "--value", str(20 + i),
         "--time", f"2026-11-21T10:00:{i:02}Z", *status])
run([binary(), "history", "write", "--db", db, "--server", "opc.tcp://press:4840", "--node", "ns=2;s=Count",
     "--path", "/Objects/Press/Count", "--type", "uint64", "--value", "18446744073709551615",
     "--time", "2026-11-21T10:00:00Z"])

registry = run_json([binary(), "history", "series", "--db", db, "--json"])
check(sorted(s["browse_path"] for s in registry) == ["/Objects/Oven/Temp", "/Objects/Press/Count"],
      f"the registry lists both series: {registry}")
oven = next(s for s in registry if s["browse_path"] == "/Objects/Oven/Temp")
check(oven["unit"] == "degC" and oven["data_type"] == "float64", "the registry keeps unit and type")

window = ["--from", "2026-11-21T10:00:00Z", "--to", "2026-11-21T10:01:00Z"]
raw = run_json([binary(), "history", "query", "--db", db, "--series", "/Objects/Oven/Temp", *window, "--json"])
values = [s["value"] for s in raw["samples"]]
check(values == [20 + i for i in range(10)], f"raw query returns every sample in order: {values}")
check(raw["samples"][3]["status"] == 0x80000000, "the Bad status is kept")
check(raw["samples"][0]["source_time"] == "2026-11-21T10:00:00Z", "times are ISO 8601 UTC")

half = run_json([binary(), "history", "query", "--db", db, "--series", "ns=2;s=Temp",
                 "--from", "2026-11-21T11:00:02+01:00", "--to", "2026-11-21T10:00:05Z", "--json"])
check([s["value"] for s in half["samples"]] == [22, 23, 24], "a node id names the series; offsets are honoured")

agg = run_json([binary(), "history", "query", "--db", db, "--series", "/Objects/Oven/Temp", *window,
                "--aggregate", "all:5s", "--json"])["aggregates"]
check(len(agg) == 2, f"two 5 s intervals: {agg}")
check(agg[0]["count"] == 4 and agg[0]["min"] == 20 and agg[0]["max"] == 24 and agg[0]["avg"] == 21.75,
      f"the Bad sample is left out of the aggregates: {agg[0]}")
check(agg[1] == {"start": "2026-11-21T10:00:05Z", "count": 5, "min": 25, "max": 29, "avg": 27},
      f"second interval: {agg[1]}")

big = run_json([binary(), "history", "query", "--db", db, "--series", "/Objects/Press/Count", *window, "--json"])
check(big["samples"][0]["value"] == 18446744073709551615, "uint64 values come back exactly")

text = run([binary(), "history", "query", "--db", db, "--series", "/Objects/Oven/Temp", *window]).stdout
check("2026-11-21T10:00:09Z" in text and "Bad (0x80000000)" in text, "the text output shows times and status")

events = run_json([binary(), "history", "events", "--db", db, *window, "--json"])
check(events == [], "no events were written")

gone = run_json([binary(), "history", "retention", "--db", db, "--keep", "1d", "--json"])
check(gone["samples_deleted"] == 11, f"retention deletes what is older than --keep: {gone}")

bad = run([binary(), "history", "series", "--db", "mysql://db/x"], check_rc=False)
check(bad.returncode == 2 and "expected sqlite:PATH or postgresql://" in bad.stderr,
      f"a bad URL is a usage error that says what is expected: {bad.stderr.strip()}")
away = run([binary(), "history", "series", "--db", "postgresql://sf@127.0.0.1:1/plant"], check_rc=False)
check(away.returncode == 1 and "unreachable" in away.stderr,
      f"an unreachable database is a clear failure: {away.stderr.strip()}")
when = run([binary(), "history", "query", "--db", db, "--series", "/Objects/Oven/Temp", "--from", "yesterday"],
           check_rc=False)
check(when.returncode == 2 and "bad time 'yesterday'" in when.stderr, "a bad time is named")
missing = run([binary(), "history", "query", "--db", db, "--series", "/Objects/Nothing"], check_rc=False)
check(missing.returncode == 2 and "no series" in missing.stderr, "an unknown series is named")
