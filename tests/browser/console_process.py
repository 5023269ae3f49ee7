"""A ``trustcbr console`` process on a temporary database, for the console's browser test
(tests/browser/console_study.py) and its load probe (docs/probes/console_load.py)."""

from __future__ import annotations

import json
import os
import re
import secrets
import subprocess
import urllib.error
import urllib.request
from pathlib import Path
from typing import Any, Dict, List, Optional, Tuple


class ConsoleStartError(RuntimeError):
    """The console did not say where it listens."""


class Console:
    """A ``trustcbr console`` process on a temporary database."""

    def __init__(self, binary: str, study: Path, folder: Path) -> None:
        self.binary = binary
        self.db = folder / "study.db"
        self.admin = secrets.token_hex(16)
        self.stderr_path = folder / "console.stderr"
        env = dict(os.environ, TRUSTCBR_CONSOLE_ADMIN_TOKEN=self.admin)
        self.stderr = open(self.stderr_path, "wb")
        command = [binary, "console", "--study", str(study), "--db", str(self.db)]
        self.process = subprocess.Popen(
            [*command, "--listen", "127.0.0.1:0"],
            stdout=subprocess.PIPE,
            stderr=self.stderr,
            env=env,
        )
        assert self.process.stdout is not None
        line = self.process.stdout.readline().decode().strip()
        match = re.fullmatch(r"listening on (http://\S+)", line)
        if not match:
            self.stop()
            raise ConsoleStartError(f"console did not start: {line!r}; {self.stderr_text()}")
        self.url = match.group(1)

    def stderr_text(self) -> str:
        if not self.stderr.closed:
            self.stderr.flush()
        return self.stderr_path.read_text(errors="replace")

    def export_events(self, out: Path) -> List[Dict[str, Any]]:
        """Writes the study's records into ``out`` with ``console export`` and returns the
        events of its ``events.jsonl``, in the file's order."""
        subprocess.run(
            [self.binary, "console", "export", str(self.db), str(out)],
            check=True,
            stdout=subprocess.DEVNULL,
        )
        return [json.loads(line) for line in (out / "events.jsonl").read_text().splitlines()]

    def stop(self) -> None:
        if self.process.poll() is None:
            self.process.terminate()
            try:
                self.process.wait(10)
            except subprocess.TimeoutExpired:
                self.process.kill()
                self.process.wait()
        self.stderr.close()

    def request(
        self, method: str, path: str, body: Any = None, token: Optional[str] = None
    ) -> Tuple[int, Any]:
        """(status, parsed JSON reply or None)."""
        data = None if body is None else json.dumps(body).encode()
        req = urllib.request.Request(self.url + path, data=data, method=method)
        req.add_header("Content-Type", "application/json")
        if token is not None:
            req.add_header("Authorization", f"Bearer {token}")
        try:
            with urllib.request.urlopen(req, timeout=30) as reply:
                text = reply.read()
                return reply.status, json.loads(text) if text else None
        except urllib.error.HTTPError as e:
            text = e.read()
            return e.code, json.loads(text) if text else None
