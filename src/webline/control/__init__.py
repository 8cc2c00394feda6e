"""Controllers: one module per family."""
