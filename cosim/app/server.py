"""`cosim app [--port N] [--open]`: the exported app (:mod:`.export`) served on 127.0.0.1.

The site is exported into a temporary folder ``TMPDIR/cosim-app-PID-*``, removed when the server
stops (Ctrl-C, or SIGTERM: exit status 143); one a killed server left is removed by the next
``cosim app``. The page is the same two files as ``cosim app --export`` writes, so what is tested
from ``file://`` is what is served. Only 127.0.0.1 is bound: the app is for the machine it runs on.
"""
from __future__ import annotations

import functools
import http.server
import signal
import threading
import webbrowser

from cosim.errors import OutputError
from cosim.outputs import temporary_folder
from cosim.app.export import export_app

HOST = "127.0.0.1"


class _Handler(http.server.SimpleHTTPRequestHandler):
    extensions_map = {**http.server.SimpleHTTPRequestHandler.extensions_map, ".js": "text/javascript"}

    def log_message(self, format, *args):  # noqa: A002 (the base class's name): no line per request
        pass


def _terminated(signum, frame):
    raise SystemExit(128 + signum)  # unwinds like Ctrl-C: the with-blocks close the socket and remove the folder


def serve(port: int = 8000, open_browser: bool = False, announce=print) -> None:
    """Export the app into a temporary folder and serve it on ``http://127.0.0.1:PORT/`` until
    interrupted.

    Parameters
    ----------
    port : int
        TCP port (0: one the system chooses).
    open_browser : bool
        Open the page in the default web browser once the server listens.
    announce : callable
        Receives the line with the URL (default: print).

    Raises
    ------
    OutputError
        If the port cannot be bound (e.g. in use).
    """
    main = threading.current_thread() is threading.main_thread()  # only there can a handler be set
    previous = signal.signal(signal.SIGTERM, _terminated) if main else None
    try:
        _serve(port, open_browser, announce)
    finally:
        if main:  # (None: a handler set outside Python, which cannot be restored from here)
            signal.signal(signal.SIGTERM, signal.SIG_DFL if previous is None else previous)


def _serve(port: int, open_browser: bool, announce) -> None:
    with temporary_folder("app") as folder:  # (removes those of ended `cosim app` processes)
        try:  # the port first: a port in use is refused before any build
            httpd = http.server.ThreadingHTTPServer((HOST, port), functools.partial(_Handler, directory=folder))
        except OSError as exc:
            raise OutputError(f"cannot serve on {HOST}:{port}: {exc.strerror or exc}") from None
        with httpd:
            export_app(folder)
            url = f"http://{HOST}:{httpd.server_address[1]}/"
            announce(f"serving the app on {url} (Ctrl-C stops)")
            if open_browser:
                webbrowser.open(url)
            httpd.serve_forever()
