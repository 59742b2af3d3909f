"""The subcommands of ``cgadyn``: one module each, with ``add_parser(subparsers)`` and
``run(args) -> exit status``; ``common`` holds what they share (argument types, the robot
argument, plot paths, JSON). ``cgadyn.cli`` registers them and handles every error once."""
