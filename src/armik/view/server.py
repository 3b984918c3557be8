"""Serving the viewer's page: viser imported on demand, the port checked before and after
the server binds it, closing that waits until the port is free again, and a stray
connection (a port probe that sends no HTTP request) said in one line, not websockets'
traceback."""

from __future__ import annotations

import contextlib
import io
import logging
import socket
import time
from typing import TYPE_CHECKING

from armik.errors import ViewerError

if TYPE_CHECKING:
    import viser

log = logging.getLogger(__name__)


def import_viser():
    """The viser module, or ``ViewerError`` telling how to install it."""
    try:
        import viser
    except ImportError:
        raise ViewerError(
            'the viewer needs viser, an optional extra: pip install "armik[view]"'
        ) from None
    return viser


def start(host: str, port: int, label: str) -> tuple[viser.ViserServer, int]:
    """A viser server on ``host:port`` (0: any free port) and the port it took; a
    ``ViewerError`` naming the port and the fix when it is in use."""
    viser = import_viser()
    _quiet_stray_connections()
    check_host(host)  # viser's server would wait forever on a host it cannot bind
    if port and not port_free(host, port):
        raise port_error(host, port)
    with contextlib.redirect_stdout(io.StringIO()):  # viser's banner: the viewer's url says it
        server = viser.ViserServer(host=host, port=port, label=label, verbose=False)
    taken = int(server.get_port())
    if port and taken != port:  # taken between the check and the bind
        server.stop()
        raise port_error(host, port)
    return server, taken


def stop(server: viser.ViserServer, host: str, port: int) -> None:
    """Stop serving and wait, up to 10 s, until the port can be bound again."""
    with contextlib.redirect_stdout(io.StringIO()):  # viser's "server stopped"
        server.stop()
    deadline = time.monotonic() + 10.0
    while not port_free(host, port) and time.monotonic() < deadline:
        time.sleep(0.05)


def port_error(host: str, port: int) -> ViewerError:
    return ViewerError(
        f"port {port} is in use on {host} (another viewer, or another program): pass another "
        f"port (--port {port + 1}, or port={port + 1}), or port 0 for any free one",
        port=port,
    )


def check_host(host: str) -> None:
    """``ViewerError`` naming ``host`` and the fix unless a server can listen on it: a name
    that does not resolve, or an address of another machine."""
    fix = (
        "pass --host 127.0.0.1 (or host='127.0.0.1') to serve this machine only, 0.0.0.0 "
        "for every network interface, or one of this machine's own addresses"
    )
    if not isinstance(host, str):
        raise ViewerError(f"host must be a name or an address (a str), got {host!r}: {fix}")
    try:
        found = socket.getaddrinfo(host or None, 0, type=socket.SOCK_STREAM)
    except (socket.gaierror, UnicodeError) as exc:
        why = getattr(exc, "strerror", None) or str(exc)
        raise ViewerError(f"host {host!r} does not resolve ({why}): {fix}") from None
    problem = ""
    for family, kind, _, _, address in found:
        with socket.socket(family, kind) as s:
            try:
                s.bind(address)
            except OSError as exc:
                problem = exc.strerror or str(exc)
                continue
        return
    raise ViewerError(f"cannot serve on host {host!r} ({problem}): {fix}")


def port_free(host: str, port: int) -> bool:
    """Whether a server could listen on ``host:port`` now (SO_REUSEADDR, as servers bind)."""
    try:
        family = socket.getaddrinfo(host or None, port, type=socket.SOCK_STREAM)[0][0]
    except socket.gaierror:
        family = socket.AF_INET
    with socket.socket(family, socket.SOCK_STREAM) as s:
        s.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        try:
            s.bind((host, port))
        except OSError:
            return False
    return True


class _StrayConnection(logging.Filter):
    """websockets logs "opening handshake failed" with a traceback when a connection sends
    no valid HTTP request (a port probe, a health check that connects and closes): this
    says it in one line on armik's logger instead, and lets every other record through."""

    def __init__(self, invalid: type[BaseException]) -> None:
        super().__init__()
        self.invalid = invalid

    def filter(self, record: logging.LogRecord) -> bool:
        exc = record.exc_info[1] if record.exc_info else None
        if not isinstance(exc, self.invalid):
            return True
        log.warning(
            "the viewer's server closed a connection that sent no valid HTTP request (%s)",
            exc.__cause__ or exc,
        )
        return False


def _quiet_stray_connections() -> None:
    """Install ``_StrayConnection`` on websockets' server logger, once."""
    from websockets.exceptions import InvalidMessage  # viser's dependency

    logger = logging.getLogger("websockets.server")
    if not any(isinstance(f, _StrayConnection) for f in logger.filters):
        logger.addFilter(_StrayConnection(InvalidMessage))
