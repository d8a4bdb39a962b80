"""Serving a machine: one host and the endpoints chosen, started and stopped together.

``serve(...)`` is what ``openmotion serve`` runs (docs/endpoints.md "Serving a machine")::

    with serve("virtual_commissioning", pace="lockstep", opcua={"port": 0}) as served:
        print(served.endpoints["opcua"].url)

Each endpoint is a class ``Endpoint(host, address, port, **options)`` with ``start()``,
``stop()`` and ``url``/``port``, found by name in ``ENDPOINTS`` and imported only when chosen:
an endpoint whose library is not installed fails with a message naming the extra to install.
"""

from __future__ import annotations

import importlib
import ipaddress
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from openmotion.core.errors import ConfigError
from openmotion.endpoints.host import MachineHost, Pace
from openmotion.endpoints.kernel_process import ProcessHost, kernel_process_available
from openmotion.scenario.schema import Scenario

__all__ = ["ENDPOINTS", "KERNELS", "LOOPBACK", "EndpointUnavailable", "Serving", "endpoint_class",
           "is_loopback", "parse_user", "read_users", "serve"]

LOOPBACK = "127.0.0.1"  #: where endpoints listen unless told otherwise
KERNEL_PROCESS, KERNEL_THREAD = "process", "thread"
KERNELS = (KERNEL_PROCESS, KERNEL_THREAD)  #: where a served machine's kernel steps (D-320)
#: endpoint name -> (module, class, the extra that installs its library)
ENDPOINTS: dict[str, tuple[str, str, str]] = {
    "opcua": ("openmotion.endpoints.opcua", "OpcUaServer", "endpoints"),
    "ads": ("openmotion.endpoints.ads", "AdsServer", "endpoints"),
}


class EndpointUnavailable(ConfigError):
    """An endpoint's library (or the endpoint itself) is not installed."""


def endpoint_class(name: str) -> type:
    """The class of the endpoint ``name``, imported now."""
    entry = ENDPOINTS.get(name)
    if entry is None:
        raise ConfigError(f"no endpoint {name!r}; one of {', '.join(ENDPOINTS)}")
    module, cls, extra = entry
    try:
        found = getattr(importlib.import_module(module), cls)
    except ImportError as error:
        raise EndpointUnavailable(
            f"the {name} endpoint is not available ({error}); install it with "
            f"pip install 'openmotion[{extra}]'") from None
    except AttributeError:
        raise EndpointUnavailable(f"the {name} endpoint is not available: {module} has no "
                                  f"{cls}") from None
    return found  # type: ignore[no-any-return]


def is_loopback(address: str) -> bool:
    """Whether ``address`` (an IP address or host name) reaches this machine only."""
    try:
        return ipaddress.ip_address(address).is_loopback
    except ValueError:
        return address.lower().rstrip(".") == "localhost"


def parse_user(text: str) -> tuple[str, str]:
    """``NAME:PASSWORD`` as (name, password); ``ConfigError`` when it is not one."""
    name, colon, password = text.partition(":")
    if not colon or not name.strip() or not password:
        raise ConfigError(f"a user is NAME:PASSWORD, not {text!r}")
    return name.strip(), password


def read_users(path: str | Path) -> dict[str, str]:
    """The users of a file: one ``NAME:PASSWORD`` a line, ``#`` comments, blank lines."""
    try:
        lines = Path(path).read_text(encoding="utf-8").splitlines()
    except OSError as error:
        raise ConfigError(f"cannot read the users file {path}: {error.strerror}") from None
    users: dict[str, str] = {}
    for number, line in enumerate(lines, 1):
        text = line.strip()
        if not text or text.startswith("#"):
            continue
        try:
            name, password = parse_user(text)
        except ConfigError:
            raise ConfigError(f"{path}:{number}: a user is NAME:PASSWORD") from None
        users[name] = password
    return users


class Serving:
    """A host and its endpoints, started and stopped together."""

    def __init__(self, host: MachineHost | ProcessHost, endpoints: Mapping[str, Mapping[str, Any]],
                 bind: str = LOOPBACK) -> None:
        if not endpoints:
            raise ConfigError(f"choose at least one endpoint: {', '.join(ENDPOINTS)}")
        self.host = host
        self.bind = bind
        self.options = {name: dict(options) for name, options in endpoints.items()}
        self.classes = {name: endpoint_class(name) for name in self.options}
        self.endpoints: dict[str, Any] = {}

    def start(self) -> Serving:
        """Start the endpoints, then the machine: its time starts when clients can connect
        (building an address space takes seconds)."""
        try:
            self.host.prepare()  # a kernel process forks before the servers' threads start
            for name, cls in self.classes.items():
                endpoint = cls(self.host, self.bind, **self.options[name])
                endpoint.start()
                self.endpoints[name] = endpoint
            if not self.host.running:
                self.host.start()
        except BaseException:
            self.stop()
            raise
        return self

    def stop(self) -> None:
        for endpoint in reversed(list(self.endpoints.values())):
            endpoint.stop()
        self.endpoints.clear()
        self.host.stop()

    def __enter__(self) -> Serving:
        return self.start()

    def __exit__(self, *exc: object) -> None:
        self.stop()

    def urls(self) -> dict[str, str]:
        """Where each endpoint listens."""
        return {name: str(getattr(endpoint, "url", f"{self.bind}:{endpoint.port}"))
                for name, endpoint in self.endpoints.items()}

    def line(self) -> str:
        """The status line: the host's pace, lateness and clients."""
        return self.host.status().line()


def serve(source: str | Path | Scenario | MachineHost | ProcessHost | None = None, *,
          pace: Pace | str = Pace.WALL, speed: float = 1.0, bind: str = LOOPBACK,
          kernel: str = KERNEL_PROCESS, kernel_priority: str = "realtime",
          opcua: bool | Mapping[str, Any] = False,
          ads: bool | Mapping[str, Any] = False) -> Serving:
    """A machine served by the endpoints chosen (``True`` or their options: ``port`` ...);
    not started: use it as a context manager or call ``start()``. ``source`` is a scenario
    (a path, a shipped example's name, a Scenario; default the shipped default) or a host.
    ``kernel``: "process" steps the machine in a process of its own, away from the servers
    (D-320; where the platform cannot fork, a thread); "thread" in the servers' process.
    ``kernel_priority``: what a kernel process asks the scheduler for (D-321): "realtime"
    (else a lower nice value), "nice" or "normal"."""
    chosen = {name: ({} if options is True else dict(options))
              for name, options in (("opcua", opcua), ("ads", ads)) if options}
    if kernel not in KERNELS:
        raise ConfigError(f"kernel must be one of {', '.join(KERNELS)}, not {kernel!r}")
    if isinstance(source, MachineHost | ProcessHost):
        host = source
    else:
        from openmotion.examples import resolve_scenario

        scenario = source if isinstance(source, Scenario) else resolve_scenario(source)
        if kernel == KERNEL_PROCESS and kernel_process_available():
            host = ProcessHost.for_scenario(scenario, pace=pace, speed=speed,
                                            priority=kernel_priority)
        else:
            host = MachineHost.for_scenario(scenario, pace=pace, speed=speed)
    return Serving(host, chosen, bind)
