"""Co-simulation of FMUs with Python components: system files, components, master algorithms."""
