"""Configuration presets shipped with the package (TOML files)."""
