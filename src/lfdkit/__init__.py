"""lfdkit: robot learning from a few noisy demonstrations.

Layers, each knowing only those below it:
``geometry`` → ``demos`` → ``mimic`` → ``imitate`` → ``emulate`` → ``robot``,
with ``metrics``, ``datasets``, ``plot`` and ``cli`` on the side.
"""

__version__ = "0.1.0"
