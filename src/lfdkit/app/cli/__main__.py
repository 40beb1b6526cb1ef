"""``python -m lfdkit.app.cli``: the ``lfdkit`` command."""

from lfdkit.app.cli.entry import main

raise SystemExit(main())
