"""Qt widgets of crustview: the only package that imports PySide6 or pyvistaqt."""
