"""`cosim app`: the paper's bicycles in the browser, running the FMUs compiled to WebAssembly.

:mod:`.export` writes the static site (``cosim app --export DIR``), :mod:`.server` serves it on
127.0.0.1 (``cosim app [--port N] [--open]``); ``static/`` holds the page's own HTML and
JavaScript and ``static/vendor/`` the vendored libraries. Design: docs/design/app.md.
"""
