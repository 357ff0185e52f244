"""The command-line interface: a thin click layer, one module per command."""
