"""The models a condition can run, by name: the seam where a new model plugs in.

A model is an options section (a subclass of :class:`ModelOptions`: frozen dataclass fields
made with :func:`~jointattention._fields.param`, each with help text and a range) whose
:meth:`~ModelOptions.build` returns an :class:`~jointattention.agent.protocol.Agent`. It is
registered in :data:`MODELS` under the name a configuration uses::

    [model]                    # the run's model (default: the paper's bootstrap model)
    kind = "bootstrap"
    learning_rate = 0.0003

    [[experiment.conditions]]  # a condition changes it: other options, or another model
    name = "n5-const0.7"
    model = { gate = { kind = "constant", rate = 0.7 } }

A new model is one module and one ``MODELS.register(name, Options)``; the runner, the
figures, the tables and the claims take it as it is.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, ClassVar

from .._fields import Registry, Section

if TYPE_CHECKING:
    import numpy as np

    from ..agent.options import AgentConfig
    from ..agent.protocol import Agent, Body

__all__ = ["MODELS", "ModelOptions"]


class ModelOptions(Section):
    """Base of the models' options sections.

    Attributes:
        readings: names of the options that are readings of the paper where it is silent;
            the claims are checked per reading, and the paper's figures show the run's own.
    """

    readings: ClassVar[tuple[str, ...]] = ()
    # The caregiver teaches it (it learns from her approval, not from its own evaluator alone):
    # the paper's claims of a self-evaluating robot do not apply to it.
    taught: ClassVar[bool] = False
    # The compiled engine runs a model only if its own class says so (a subclass does not
    # inherit it: the compiled loop knows only what it was written for), and not the option
    # values named here (e.g. a learning module it has no kernels for).
    compiled: ClassVar[bool] = False
    python_only: ClassVar[dict[str, tuple]] = {}

    def build(self, mechanisms: AgentConfig, body: Body, rng: np.random.Generator) -> Agent:
        """The untrained agent.

        Built from these options, the robot's shared mechanisms (``mechanisms``: the
        configuration's ``[agent]`` section), its body, and its own random generator.
        """
        raise NotImplementedError

    def compiled_refusal(self) -> str | None:
        """Why the compiled engine cannot run these options, as an error message (None if it can).

        The model's own class and its gate's own class must declare ``compiled = True``.
        """
        gate = getattr(self, "gate", None)
        values = [(k, getattr(self, k)) for k, v in type(self).python_only.items()
                  if getattr(self, k) in v]
        if not type(self).__dict__.get("compiled", False):
            what = f"model kind {self._kind()!r}"
        elif gate is not None and not type(gate).__dict__.get("compiled", False):
            what = f"gate kind {gate.label!r}"
        elif values:
            what = f"{values[0][0]} {values[0][1]!r}"
        else:
            return None
        return (f"experiment.engine = 'compiled' does not run {what}; expected a model of kind "
                f"{_compiled_kinds(MODELS)} (with a gate of kind {_compiled_kinds(_gates())}), "
                "or experiment.engine = 'python' or 'auto'")

    def save_refusal(self) -> str | None:
        """Why a model file cannot hold this model, as the reason's words (None if it can).

        A model that can be saved returns None and its agent has ``saved_arrays``,
        ``saved_shapes`` and ``load_arrays`` (:mod:`jointattention.deploy.saved`).
        """
        return f"model kind {self._kind()!r} is not saved"

    def _kind(self) -> str:
        """The registered name of this kind, or the class's name if it is not registered."""
        try:
            return MODELS.name_of(self)
        except KeyError:
            return type(self).__name__

    @property
    def label(self) -> str:
        """A short name for figures and tables: the model's name, and its gate's if any."""
        gate = getattr(self, "gate", None)
        name = MODELS.name_of(self)
        return name if gate is None else f"{name}, {gate.label}"


def _gates() -> Registry:
    """The gates' registry (imported when a refusal is written: the agent layer's)."""
    from ..agent.gates import GATES

    return GATES


def _compiled_kinds(registry: Registry) -> str:
    """The registered kinds whose own class declares ``compiled = True``, as words."""
    names = sorted(n for n in registry if registry[n].__dict__.get("compiled", False))
    return ", ".join(names[:-1]) + f" or {names[-1]}" if len(names) > 1 else "".join(names)


MODELS = Registry("model", {"bootstrap": "jointattention.models.bootstrap:BootstrapOptions",
                            "teacher": "jointattention.models.teacher:TeacherOptions",
                            "rl": "jointattention.models.rl:RLOptions",
                            "developmental":
                                "jointattention.models.developmental:DevelopmentalOptions"})
