"""``lfdkit teach``: the local web page."""

from __future__ import annotations

import argparse

from lfdkit.app.cli.common import (
    CommandError,
    bounded_int,
    tell,
)

__all__ = ["add_options", "run_command"]


def run_command(args: argparse.Namespace) -> None:
    try:  # the optional extra `teach`, imported only here
        import starlette  # noqa: F401
        import uvicorn  # noqa: F401
    except ImportError as exc:
        raise CommandError(
            f"the teach page needs Starlette and uvicorn ({exc.name} is missing); "
            'install them with: pip install "lfdkit[teach]"'
        ) from None
    from lfdkit.app.teach.server import is_loopback, serve

    if not is_loopback(args.host):
        tell(
            args,
            f"lfdkit teach: warning: listening on {args.host}: anyone who can reach this "
            "machine on port "
            f"{args.port} can use the page and make it learn; use the default 127.0.0.1 "
            "unless you mean that",
            level=0,
        )
    serve(
        args.host,
        args.port,
        open_browser=args.open,
        say=lambda line: tell(args, f"lfdkit teach: {line}"),
        # The URL is the command's output: on stdout, even under -q (with --port 0
        # it is the only way to learn the port bound).
        show_url=lambda url: print(url, flush=True),
        warn=lambda line: tell(args, f"lfdkit teach: {line}", level=0),
    )


def add_options(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "--port",
        type=bounded_int(0, 65535),
        default=8765,
        help="port to listen on (default %(default)s; 0: a free one; the page's URL is "
        "printed on stdout, even with -q)",
    )
    parser.add_argument(
        "--host",
        default="127.0.0.1",
        help="address to listen on (default %(default)s, this machine only; another "
        "address exposes the page to the network and prints a warning)",
    )
    parser.add_argument(
        "--open",
        action="store_true",
        help="open the page in the default web browser (a warning with the URL to open "
        "by hand when none can be opened, e.g. without a display)",
    )
