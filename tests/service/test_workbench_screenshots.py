"""Each workbench page rendered in headless Chromium at a fixed viewport matches its
reviewed reference in ``tests/service/screenshots/`` (at most ``MAX_CHANGED`` of the pixels
changed), and a broken picture does not (issue 35). ``python -m service.screenshots
--update`` regenerates the references and the README's ``docs/screenshots/``."""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import pytest

from service.launch import start_server
from service.screenshots import PAGES, REFERENCES, SERVER_ENV, compare, render
from tests.service.test_workbench import browser, chromium  # noqa: F401

pytestmark = [
    pytest.mark.browser,
    pytest.mark.skipif(chromium() is None, reason="browser tests skipped: no Chromium found"),
]


@pytest.fixture(scope="module")
def server(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Any]:
    """A service as ``python -m service.screenshots`` renders on (the default cell)."""
    s = start_server(tmp_path_factory.mktemp("screenshots"), 60.0, **SERVER_ENV)
    yield s
    s.kill()


@pytest.mark.parametrize("name", list(PAGES))
def test_each_page_matches_its_reviewed_reference(browser: Any, server: Any, name: str) -> None:  # noqa: F811
    assert (REFERENCES / f"{name}.png").exists(), "no reference: python -m service.screenshots --update"
    result = compare(name, render(browser, server.url, name))
    assert result.ok, f"{result} (render and difference in tests/artifacts/screenshots/)"


@pytest.mark.parametrize(("name", "css"), [
    ("part", ".uplot canvas { filter: grayscale(1); }"),  # the plots lose their colours (orange regions grey)
    ("plan", ".jaw { display: none; }"),  # the jaws missing from the animation
    ("editor", ".editor-vertex { r: 3px; }"),  # handles drawn too large
])
def test_a_broken_picture_fails_the_comparison(browser: Any, server: Any, name: str, css: str, tmp_path: Any) -> None:  # noqa: F811
    result = compare(name, render(browser, server.url, name, css=css), artifacts=tmp_path)
    assert not result.ok and (tmp_path / f"{name}-diff.png").exists()
