#!/usr/bin/env python3
"""Runs the shell command blocks of README.md and docs/*.md as written, from the repository root.

Every ```sh block of a document is a list of commands a user may copy; each one must exit 0 and
leave the files it names (--out, --svg, --export, --trajectory-out, map convert's output). The few
changes made to a command before it runs are the ones listed in docs/ci.md ("The doc test"):

  build/bin/starnav, or starnav at the start of a command  -> the CLI under test
  /tmp/ and a leading out/ in a path                      -> a scratch folder of this test
  make demo                                                -> make demo BUILD=<the build under test>
  DATA                                                     -> ../shared/datasets (the command is
                                                              skipped when that folder is absent,
                                                              and so is every later command of its
                                                              block: they may read what it writes)
  --seeds N (N > 2) -> --seeds 2; --queries N (N > 50) -> --queries 50; bench kitti -> --frames 3;
  bench slam without --logs -> --logs mit-csail; slam3d on a dataset -> --frames 3
                                                           (long benches, shortened; the shortest log)
  a server (view without --export)                         -> --port 0, the page fetched, then Ctrl-C
  sim --live / --live-wait                                 -> --port 0; with --live-wait a viewer
                                                              connects to /events

Every ```python block is run the same way, as one script: /usr/bin/python3 (the interpreter running
this) with the build's package first on the path (PYTHONPATH=BUILD_DIR/python, as `make test` builds
it), from the repository root, /tmp/ replaced as above; it must exit 0. A block that names ../shared
is skipped when that folder is absent; every python block is skipped when the build has no Python
package (configured with -DSTARNAV_WITH_PYTHON=OFF).

A block right after a line `<!-- doc-test: skip REASON -->` is not run (a command that changes the
repository, say).

  run_doc_commands.py --list ROOT            the runnable blocks, one "FILE:INDEX" per line ("FILE:pyINDEX" for python)
  run_doc_commands.py --run FILE:INDEX ROOT CLI BUILD_DIR SCRATCH
"""
import os
import re
import shlex
import shutil
import signal
import subprocess
import sys
import threading
import time
import urllib.request

DOCS = ["README.md"]  # and docs/*.md, found at run time


def documents(root):
    docs = list(DOCS)
    docs += sorted("docs/" + f for f in os.listdir(os.path.join(root, "docs")) if f.endswith(".md"))
    return docs


def blocks(path, language="sh"):
    """The ```sh (or ```python) blocks of a Markdown file: (index, [lines]), skipped ones left out."""
    lines = open(path, encoding="utf-8").read().split("\n")
    out, index, i = [], 0, 0
    while i < len(lines):
        if lines[i].strip() == "```" + language:
            skip = i > 0 and lines[i - 1].strip().startswith("<!-- doc-test: skip")
            j = i + 1
            body = []
            while j < len(lines) and lines[j].strip() != "```":
                body.append(lines[j])
                j += 1
            if not skip:
                out.append((index, body))
            index += 1
            i = j
        i += 1
    return out


def commands(body):
    """Continuation lines joined; comment lines and blank lines dropped."""
    joined, current = [], ""
    for line in body:
        if line.endswith("\\"):
            current += line[:-1] + " "
            continue
        current += line
        if current.strip() and not current.strip().startswith("#"):
            joined.append(current.strip())
        current = ""
    return joined


def strip_comment(cmd):
    """A trailing `# comment` (a # outside quotes, after a space) removed."""
    quote = None
    for k, ch in enumerate(cmd):
        if quote:
            if ch == quote:
                quote = None
        elif ch in "'\"":
            quote = ch
        elif ch == "#" and (k == 0 or cmd[k - 1].isspace()):
            return cmd[:k].rstrip()
    return cmd


# /tmp/ where a path starts (not inside another path, such as a clone's under /tmp).
TMP_PATH = re.compile(r"(?<![\w./~-])/tmp/")


class Runner:
    def __init__(self, root, cli, build, scratch):
        self.root, self.cli, self.build, self.scratch = root, cli, build, scratch
        self.shared = os.path.normpath(os.path.join(root, "..", "shared", "datasets"))
        self.env = dict(os.environ)
        self.env.pop("DATA", None)
        self.assignments = []  # VAR=value lines, run before each command
        self.skipped_for_data = None  # the first command of the block skipped for the absent datasets

    def rewrite(self, cmd):
        cmd = strip_comment(cmd)
        # /tmp/ first and only where a path starts: the CLI's own path (a clone under /tmp) stays.
        cmd = re.sub(TMP_PATH, self.scratch.replace("\\", "\\\\") + "/", cmd)
        cmd = re.sub(r"(^|(?<=[\s;&|(]))build/bin/starnav\b", self.cli, cmd)
        cmd = re.sub(r"(^|(?<=&& )|(?<=; ))starnav\b", self.cli, cmd)
        cmd = re.sub(r"(?<=\s)out/", self.scratch + "/out/", cmd)
        if re.match(r"^make demo\b", cmd):
            cmd += " BUILD=" + shlex.quote(self.build) + self.make_options()
        cmd = re.sub(r"--seeds (\d+)", lambda m: "--seeds " + str(min(int(m.group(1)), 2)), cmd)
        cmd = re.sub(r"--queries (\d+)", lambda m: "--queries " + str(min(int(m.group(1)), 50)), cmd)
        lidar_dataset_run = " bench kitti" in cmd or re.search(r"\bslam3d (\$DATA|\S*datasets)/", cmd)
        if lidar_dataset_run and "--frames" not in cmd:
            cmd += " --frames 3"
        if " bench slam" in cmd and "--logs" not in cmd:
            cmd += " --logs mit-csail"
        return cmd

    def make_options(self):
        """GDAL= and PCL= as the build under test was configured, so make's build step is a no-op."""
        opts = ""
        try:
            cache = open(os.path.join(self.build, "CMakeCache.txt"), encoding="utf-8").read()
        except OSError:
            return opts
        for var, option in (("GDAL", "STARNAV_WITH_GDAL"), ("PCL", "STARNAV_WITH_PCL")):
            m = re.search(r"^%s:BOOL=(\w+)$" % option, cache, re.M)
            if m:
                opts += " %s=%s" % (var, "ON" if m.group(1).upper() in ("ON", "TRUE", "1", "YES") else "OFF")
        return opts

    def needs_data(self, cmd):
        return "$DATA" in cmd or "${DATA" in cmd or "../shared" in cmd

    def promised_outputs(self, cmd):
        words = shlex.split(cmd, comments=True)
        out = []
        for k, w in enumerate(words[:-1]):
            if w in ("--out", "--svg", "--export", "--trajectory-out"):
                out.append(words[k + 1])
        if len(words) >= 4 and words[1:3] == ["map", "convert"]:
            out.append(words[4] if len(words) > 4 and not words[3].startswith("-") else words[3])
        return [o for o in out if not o.startswith("-")]

    def run(self, cmd):
        """Returns (status, seconds, detail): status ok | skip | fail."""
        if re.match(r"^[A-Za-z_][A-Za-z0-9_]*=", cmd) and " " not in cmd.split("=", 1)[0]:
            self.assignments.append(cmd)
            return "ok", 0.0, "set " + cmd.split("=", 1)[0]
        if self.needs_data(cmd) and not os.path.isdir(self.shared):
            self.skipped_for_data = self.skipped_for_data or cmd
            return "skip", 0.0, "needs the datasets (../shared/datasets is absent)"
        if self.skipped_for_data:
            return "skip", 0.0, "follows a command skipped for the absent datasets (it may read what that one writes)"
        env = dict(self.env)
        if os.path.isdir(self.shared):
            env["DATA"] = self.shared
        cmd = self.rewrite(cmd)
        prelude = "set -e\n" + "".join(a + "\n" for a in self.assignments)
        t0 = time.monotonic()
        words = cmd.split()
        serving = len(words) > 1 and words[0] == self.cli and words[1] == "view" and "--export" not in words
        live = len(words) > 1 and words[0] == self.cli and words[1] == "sim" and "--live" in words
        if serving or live:
            if "--port" not in words:
                cmd += " --port 0"
            # exec: Ctrl-C reaches starnav itself.
            return self.run_server(prelude + "exec " + cmd + "\n", env, t0, waits_for_viewer="--live-wait" in words,
                                   stops_itself=live)
        p = subprocess.run(["bash", "-c", prelude + cmd + "\n"], cwd=self.root, env=env, capture_output=True, text=True, timeout=900)
        dt = time.monotonic() - t0
        if p.returncode != 0:
            return "fail", dt, "exit %d\n%s%s" % (p.returncode, tail(p.stdout), tail(p.stderr))
        missing = []
        for o in self.promised_outputs(cmd):
            path = o if os.path.isabs(o) else os.path.join(self.root, o)
            if not os.path.exists(path) or (os.path.isfile(path) and os.path.getsize(path) == 0) or (
                    os.path.isdir(path) and not os.listdir(path)):
                missing.append(o)
        if missing:
            return "fail", dt, "exit 0 but missing or empty: " + ", ".join(missing)
        return "ok", dt, ""

    def run_server(self, script, env, t0, waits_for_viewer, stops_itself):
        p = subprocess.Popen(["bash", "-c", script], cwd=self.root, env=env, stdout=subprocess.PIPE,
                             stderr=subprocess.STDOUT, text=True, start_new_session=True)
        output = []
        url = None
        deadline = time.monotonic() + 120
        while url is None and time.monotonic() < deadline:
            line = p.stdout.readline()
            if not line:
                break
            output.append(line)
            m = re.search(r"(http://127\.0\.0\.1:\d+/)", line)
            if m:
                url = m.group(1)
        if url is None:
            p.kill()
            return "fail", time.monotonic() - t0, "no URL printed\n" + tail("".join(output))
        reader = threading.Thread(target=lambda: output.extend(p.stdout), daemon=True)
        reader.start()
        try:
            if waits_for_viewer:
                events = urllib.request.urlopen(url + "events", timeout=60)
                threading.Thread(target=lambda: events.read(), daemon=True).start()
            page = urllib.request.urlopen(url, timeout=30).read().decode("utf-8", "replace")
        except Exception as e:  # the failure is the result
            p.kill()
            return "fail", time.monotonic() - t0, "fetching %s: %s" % (url, e)
        if "<html" not in page.lower():
            p.kill()
            return "fail", time.monotonic() - t0, "%s did not serve the viewer's page" % url
        if not stops_itself:
            os.killpg(p.pid, signal.SIGINT)  # Ctrl-C, as the docs say
        try:
            rc = p.wait(timeout=300)
        except subprocess.TimeoutExpired:
            p.kill()
            return "fail", time.monotonic() - t0, "did not stop"
        reader.join(timeout=5)
        if rc != 0:
            return "fail", time.monotonic() - t0, "exit %d\n%s" % (rc, tail("".join(output)))
        return "ok", time.monotonic() - t0, "served " + url


def tail(text, n=15):
    lines = text.strip().split("\n")
    return "\n".join("    " + l for l in lines[-n:] if l) + ("\n" if text.strip() else "")


def run_python_block(doc, index, body, root, build, scratch):
    """One ```python block as a script; 0 when it ran (or was skipped), 1 when it failed."""
    code = "\n".join(body)
    name = "%s python block %d" % (doc, index)
    package = os.path.join(build, "python")
    if not os.path.isfile(os.path.join(package, "starnav", "__init__.py")):
        print("skip  %s: the build has no Python package (STARNAV_WITH_PYTHON=OFF)" % name)
        return 0
    shared = os.path.normpath(os.path.join(root, "..", "shared"))
    if "../shared" in code and not os.path.isdir(shared):
        print("skip  %s: needs ../shared (absent)" % name)
        return 0
    code = re.sub(TMP_PATH, scratch.replace("\\", "\\\\") + "/", code)
    env = dict(os.environ, MPLBACKEND="Agg")
    env["PYTHONPATH"] = package + (os.pathsep + env["PYTHONPATH"] if env.get("PYTHONPATH") else "")
    t0 = time.monotonic()
    p = subprocess.run([sys.executable, "-c", code], cwd=root, env=env, capture_output=True, text=True, timeout=900)
    status = "ok" if p.returncode == 0 else "fail"
    print("%-4s %6.1f s  %s" % (status, time.monotonic() - t0, name))
    if p.returncode != 0:
        print("      exit %d\n%s%s" % (p.returncode, tail(p.stdout), tail(p.stderr)))
        return 1
    print("%s block py%d: ran as written" % (doc, index))
    return 0


def main(argv):
    if len(argv) == 3 and argv[1] == "--list":
        root = argv[2]
        for doc in documents(root):
            for index, body in blocks(os.path.join(root, doc)):
                if commands(body):
                    print("%s:%d" % (doc, index))
            for index, body in blocks(os.path.join(root, doc), "python"):
                if "".join(body).strip():
                    print("%s:py%d" % (doc, index))
        return 0
    if len(argv) == 7 and argv[1] == "--run":
        doc, index = argv[2].rsplit(":", 1)
        root, cli, build, scratch = (os.path.abspath(a) for a in argv[3:7])
        shutil.rmtree(scratch, ignore_errors=True)
        os.makedirs(scratch)
        if index.startswith("py"):
            found = dict(blocks(os.path.join(root, doc), "python")).get(int(index[2:]))
            if found is None:
                print("%s has no python block %s" % (doc, index), file=sys.stderr)
                return 2
            return run_python_block(doc, int(index[2:]), found, root, build, scratch)
        found = dict(blocks(os.path.join(root, doc))).get(int(index))
        if found is None:
            print("%s has no runnable block %s" % (doc, index), file=sys.stderr)
            return 2
        runner = Runner(root, cli, build, scratch)
        failed = 0
        for cmd in commands(found):
            status, dt, detail = runner.run(cmd)
            print("%-4s %6.1f s  %s" % (status, dt, cmd))
            ran = runner.rewrite(cmd) if status != "skip" and "=" not in cmd.split(" ")[0] else None
            if ran and ran.replace(runner.cli, "starnav") != strip_comment(cmd).replace("build/bin/starnav", "starnav"):
                print("             (ran as: %s)" % ran)
            if detail and status != "ok":
                print("      " + detail.rstrip().replace("\n", "\n      "))
            failed += status == "fail"
        print("%s block %s: %s" % (doc, index, "%d failed" % failed if failed else "every command ran as written"))
        return 1 if failed else 0
    print(__doc__, file=sys.stderr)
    return 2


if __name__ == "__main__":
    sys.exit(main(sys.argv))
