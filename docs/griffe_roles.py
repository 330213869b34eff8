"""A griffe extension: the docstrings' Sphinx roles become the manual's cross-references.

The package's docstrings name other objects with Sphinx roles (``:func:`~.preflight.check_runs```),
which read well in ``help()`` but which mkdocstrings shows as literal text. This extension
(``mkdocs.yml``: the python handler's ``extensions``) rewrites each role, once the package is
loaded, into an optional autorefs cross-reference: a link where the manual renders the target,
plain code where it does not (a private module, numpy). Targets are resolved as Sphinx does:
absolute, then from the docstring's own module and its parents, then by a unique suffix.

``make docs`` runs it, and then checks that no literal role is left in the built manual.
"""

from __future__ import annotations

import html
import re

import griffe

ROLE = re.compile(r":(?:py:)?(?:func|meth|class|mod|data|attr|exc|obj|const)"
                  r":`(?P<body>[^`]+)`")
_TITLED = re.compile(r"(?P<title>.*?)\s*<(?P<target>[^>]+)>$", re.DOTALL)


def _objects(obj: griffe.Object):
    """``obj`` and every member under it, aliases left out (their targets are walked)."""
    yield obj
    for member in obj.members.values():
        if not member.is_alias:
            yield from _objects(member)


class SphinxRoles(griffe.Extension):
    """Rewrite the Sphinx roles of every docstring of the package into cross-references."""

    def on_package(self, *, pkg: griffe.Module, **kwargs) -> None:
        """Resolve and rewrite the roles of every object of ``pkg``."""
        objects = list(_objects(pkg))
        paths = {o.path for o in objects} | {
            f"{o.path}.{name}" for o in objects for name, m in o.members.items() if m.is_alias}
        by_suffix: dict[str, list[str]] = {}
        for path in paths:
            parts = path.split(".")
            for i in range(1, len(parts)):
                by_suffix.setdefault(".".join(parts[i:]), []).append(path)
        for obj in objects:
            if obj.docstring is not None and ":`" in obj.docstring.value:
                obj.docstring.value = ROLE.sub(
                    lambda m, obj=obj: self._reference(m["body"], obj, paths, by_suffix),
                    obj.docstring.value)

    @staticmethod
    def _reference(body: str, obj: griffe.Object, paths: set[str],
                   by_suffix: dict[str, list[str]]) -> str:
        """One role's body (``~.a.b``, ``a.b``, ``title <a.b>``) as an optional autoref."""
        titled = _TITLED.match(body)
        title, target = (titled["title"], titled["target"]) if titled else (None, body)
        target = " ".join(target.split())
        short = target.startswith("~")
        target = target.lstrip("~!")
        name = target.lstrip(".")
        scopes = [obj.path]
        while "." in scopes[-1]:
            scopes.append(scopes[-1].rsplit(".", 1)[0])
        found = next((c for c in ([] if target.startswith(".") else [target])
                      + [f"{s}.{name}" for s in scopes] if c in paths), None)
        if found is None and len(by_suffix.get(name, [])) == 1:
            found = by_suffix[name][0]
        if title is None:
            title = name.rsplit(".", 1)[-1] if short else name
        text = f"<code>{html.escape(title.strip())}</code>"
        return (f'<autoref identifier="{html.escape(found or name)}" optional>{text}'
                "</autoref>")
