"""The UI's panels. Each module renders one view (HTML/SVG strings from pure functions, so they are
testable without a browser) and, where it has controls, a small class that wires them into viser."""
