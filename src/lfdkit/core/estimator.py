"""scikit-learn's estimator conventions, without importing scikit-learn.

lfdkit's estimators (:class:`lfdkit.mimic.MeanPath`, :class:`lfdkit.mimic.GMR`,
:class:`lfdkit.imitate.DMP`, :class:`lfdkit.skill.Skill`, ...) take their
parameters in the constructor and keep each under its own name, so that
``get_params``, ``set_params`` and :func:`sklearn.base.clone` work on them.
Deriving them from ``sklearn.base.BaseEstimator`` for that cost every
``import lfdkit.mimic`` (and ``lfdkit --help``) the import of scikit-learn and
most of SciPy, seconds; :class:`Estimator` gives the same three conventions
in a few lines. scikit-learn is imported only where it is used (EM in
:class:`~lfdkit.mimic.GMR`) and to raise its ``NotFittedError``
(:func:`not_fitted`), which callers may catch as before.
"""

from __future__ import annotations

import inspect
from collections.abc import Callable, Iterable
from typing import Any, ClassVar

__all__ = ["Estimator", "check_fitted", "not_fitted"]


class Estimator:
    """Parameters by constructor name: ``get_params``, ``set_params``, a short ``repr``.

    A subclass declares what its parameters may be in ``_parameter_constraints``
    (name → constraint of :mod:`lfdkit.core.constraints`); ``fit`` calls
    :meth:`_validate_params` once when it starts.
    """

    #: Parameter name → ``constraint(value, name)``, checked in this order (a base
    #: class's rows first) by :meth:`_validate_params`.
    _parameter_constraints: ClassVar[dict[str, Callable[[Any, str], Any]]] = {}

    def _validate_params(self) -> dict[str, Any]:
        """Check every parameter against the tables of the class and its bases.

        Returns
        -------
        dict
            The checked values by name (an ``int`` for an integer, a ``float``
            for a number), in the tables' order.

        Raises
        ------
        ValueError, TypeError
            The first parameter refused, on one line naming it and its value.
        """
        checked: dict[str, Any] = {}
        for cls in reversed(type(self).__mro__):
            for name, constraint in vars(cls).get("_parameter_constraints", {}).items():
                checked[name] = constraint(getattr(self, name), name)
        return checked

    @classmethod
    def _param_names(cls) -> list[str]:
        """The constructor's parameter names, sorted (as scikit-learn lists them)."""
        signature = inspect.signature(cls.__init__)
        return sorted(
            name
            for name, p in signature.parameters.items()
            if name != "self" and p.kind not in (p.VAR_POSITIONAL, p.VAR_KEYWORD)
        )

    def get_params(self, deep: bool = True) -> dict[str, Any]:
        """The constructor parameters and their values.

        Parameters
        ----------
        deep : bool
            Also list the parameters of parameter values that have
            ``get_params`` themselves, as ``name__parameter``.
        """
        params: dict[str, Any] = {}
        for name in self._param_names():
            value = getattr(self, name)
            if deep and hasattr(value, "get_params") and not isinstance(value, type):
                params.update((f"{name}__{k}", v) for k, v in value.get_params().items())
            params[name] = value
        return params

    def set_params(self, **params: Any) -> Estimator:
        """Set constructor parameters by name (``name__parameter`` for nested ones).

        Returns
        -------
        self
        """
        names = self._param_names()
        nested: dict[str, dict[str, Any]] = {}
        for key, value in params.items():
            name, _, sub = key.partition("__")
            if name not in names:
                raise ValueError(
                    f"Invalid parameter {name!r} for estimator {self}. "
                    f"Valid parameters are: {names!r}."
                )
            if sub:
                nested.setdefault(name, {})[sub] = value
            else:
                setattr(self, name, value)
        for name, sub_params in nested.items():
            getattr(self, name).set_params(**sub_params)
        return self

    def __repr__(self) -> str:
        """``Class(param=value, ...)`` with the parameters that differ from their defaults."""
        defaults = {
            name: p.default for name, p in inspect.signature(type(self).__init__).parameters.items()
        }
        shown = []
        for name in self._param_names():
            value = getattr(self, name, None)
            default = defaults.get(name, inspect.Parameter.empty)
            if not _same(value, default):
                shown.append(f"{name}={_short(value)}")
        return f"{type(self).__name__}({', '.join(shown)})"


def _same(value: Any, default: Any) -> bool:
    if value is default:
        return True
    if hasattr(value, "shape") or hasattr(default, "shape"):
        return False  # an array given differs from any scalar default
    try:
        return bool(value == default) and type(value) is type(default)
    except Exception:
        return False


def _short(value: Any) -> str:
    if hasattr(value, "shape"):
        return f"array of shape {tuple(value.shape)}"
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."


def not_fitted(message: str) -> Exception:
    """scikit-learn's ``NotFittedError`` with ``message`` (imported only now, to raise it)."""
    from sklearn.exceptions import NotFittedError

    return NotFittedError(message)


def check_fitted(
    estimator: Any, attributes: str | Iterable[str], message: str | None = None
) -> None:
    """Raise :func:`not_fitted` unless ``estimator`` has every one of ``attributes``.

    Like ``sklearn.utils.validation.check_is_fitted`` with named attributes.
    """
    names = (attributes,) if isinstance(attributes, str) else tuple(attributes)
    if not all(hasattr(estimator, name) for name in names):
        name = type(estimator).__name__
        raise not_fitted(
            message
            or f"This {name} instance is not fitted yet. Call 'fit' with appropriate "
            "arguments before using this estimator."
        )
