"""The two gripper actions and their one spelling (docs/conventions.md §4).

``squeeze`` and ``push_grasp`` are the names in every document, record, HTTP body and
CLI output; ``push-grasp`` (the paper's and the CLI's habit) is accepted on input and
read as ``push_grasp``.

>>> parse_action("push-grasp")
'push_grasp'
>>> parse_action("grasp")
Traceback (most recent call last):
...
algrasp.errors.ConfigError: action: expected squeeze or push_grasp (push-grasp is read as push_grasp), got 'grasp'
"""

from __future__ import annotations

from typing import Literal, cast

from algrasp.errors import ConfigError

Action = Literal["squeeze", "push_grasp"]
ACTIONS: tuple[Action, ...] = ("squeeze", "push_grasp")
ALIASES: dict[str, Action] = {"push-grasp": "push_grasp"}
"""Other spellings accepted on input."""


def parse_action(value: object, field: str = "action") -> Action:
    """The action ``value`` names; ConfigError naming ``field`` otherwise."""
    if isinstance(value, str):
        name = ALIASES.get(value, value)
        if name in ACTIONS:
            return cast(Action, name)
    raise ConfigError(field, f"expected squeeze or push_grasp (push-grasp is read as push_grasp), got {value!r}")
