"""One module per ``rocknroller`` subcommand: ``register(subparsers)`` and ``run(args)``."""
