"""A Dask scheduler reached safely: an address is probed before ``distributed`` is handed it.

``distributed.Client(address, timeout=...)`` bounds the TCP connection but not the handshake
that follows: a port that accepts and never answers hangs it for ever, and a service that is
no scheduler (a web server) is read as Dask's frames, whose 8-byte length prefix then asks
for exabytes. A scheduler sends its handshake as soon as it accepts a connection, so the
probe connects (``CONNECT_SECONDS``), waits for those first 8 bytes (``HANDSHAKE_SECONDS``)
and checks that they announce a message of a plausible size; only then is the ``Client``
made. TLS and other schemes are probed for the connection alone.
"""

from __future__ import annotations

import socket
import struct
from typing import Any

from webline.errors import ArgumentError

#: seconds to wait for the TCP connection
CONNECT_SECONDS = 10.0
#: seconds to wait for the scheduler's first bytes once connected
HANDSHAKE_SECONDS = 10.0
#: largest first message a scheduler sends [bytes] (its handshake is a few hundred bytes)
MAX_HANDSHAKE_BYTES = 1 << 20

_HINT = "give the address of a Dask scheduler (tcp://host:8786), 'local' or a Client"


def _refuse(address: str, why: str) -> ArgumentError:
    return ArgumentError(f"scheduler: cannot reach a Dask scheduler at {address!r} ({why}); "
                         f"{_HINT}")


def probe(address: str) -> None:
    """Raise ``ArgumentError`` unless something at ``address`` answers as a Dask scheduler
    would within ``CONNECT_SECONDS`` + ``HANDSHAKE_SECONDS``."""
    from distributed.comm.addressing import parse_address, parse_host_port

    try:
        scheme, location = parse_address(address)
        host, port = parse_host_port(location)
    except (ValueError, TypeError) as exc:  # not an address
        raise _refuse(address, str(exc)) from None
    try:
        with socket.create_connection((host, port), timeout=CONNECT_SECONDS) as sock:
            if scheme != "tcp":
                return
            sock.settimeout(HANDSHAKE_SECONDS)
            head = b""
            while len(head) < 8:
                got = sock.recv(8 - len(head))
                if not got:
                    raise _refuse(address, "a service that closed the connection unasked: "
                                  "not a Dask scheduler")
                head += got
    except TimeoutError:
        raise _refuse(address, "nothing answered as a Dask scheduler within "
                      f"{CONNECT_SECONDS + HANDSHAKE_SECONDS:.0f} s") from None
    except OSError as exc:
        raise _refuse(address, exc.strerror or str(exc)) from None
    (size,) = struct.unpack("<Q", head)
    if not 0 < size <= MAX_HANDSHAKE_BYTES:
        raise _refuse(address, f"a service that is not a Dask scheduler: its first message "
                      f"announces {size:.3g} bytes")


def connect(address: str) -> Any:
    """A ``distributed.Client`` of the scheduler at ``address``, probed first (``probe``)."""
    from distributed import Client

    probe(address)
    try:
        return Client(address, timeout=CONNECT_SECONDS + HANDSHAKE_SECONDS)
    except (OSError, ValueError, TypeError, MemoryError) as exc:
        raise _refuse(address, str(exc)) from None
