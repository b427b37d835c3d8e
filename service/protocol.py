"""uvicorn's HTTP/1.1 protocol with a header timeout: a client that connects and sends its
request line and headers a byte at a time (slowloris) is disconnected after
``header_timeout_s``, instead of holding a connection for as long as it likes (uvicorn
itself bounds only idle keep-alive connections). The body has its own bound
(``RequestGuard``'s body timeout)."""

from __future__ import annotations

import asyncio
from typing import Any

import h11
from uvicorn.protocols.http.h11_impl import H11Protocol


def with_header_timeout(header_timeout_s: float) -> type[H11Protocol]:
    """The protocol class to pass as ``uvicorn.run(http=...)``."""

    class HeaderTimeoutProtocol(H11Protocol):
        _header_timer: asyncio.TimerHandle | None = None

        def connection_made(self, transport: asyncio.Transport) -> None:  # type: ignore[override]
            super().connection_made(transport)
            self._arm()

        def connection_lost(self, exc: Exception | None) -> None:
            if self._header_timer is not None:
                self._header_timer.cancel()
            super().connection_lost(exc)

        def on_response_complete(self) -> None:
            super().on_response_complete()
            self._arm()  # the next request on this connection gets the same bound

        def _arm(self) -> None:
            if self._header_timer is not None:
                self._header_timer.cancel()
            self._header_timer = self.loop.call_later(header_timeout_s, self._expired)

        def _expired(self, *_: Any) -> None:
            # Still before a whole request head (h11: the client is IDLE until it is parsed).
            if self.conn.their_state is h11.IDLE and not self.transport.is_closing():
                self.transport.close()

    return HeaderTimeoutProtocol
