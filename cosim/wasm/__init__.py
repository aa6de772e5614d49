"""The FMUs as WebAssembly: the FMI 2.0 FMU's own C sources (generated model code and the FMI
runtime) with a small JavaScript-friendly API (``wasm_api.c``), compiled by Zig's clang for
``wasm32-wasi`` (:func:`cosim.wasm.build.build_wasm`, ``cosim build --wasm``), and an ES module
that runs it in a browser (``fmu.js``)."""
