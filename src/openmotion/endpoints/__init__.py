"""Endpoints: the machine served to the tools engineers already use (docs/endpoints.md).

``MachineHost`` runs one machine on a kernel thread, paced by the wall clock or in lockstep
with a client, and publishes snapshots of its machine model (``ProcessHost``: the same, the
kernel in a process of its own, away from the servers); the OPC UA server, the ADS
server and the FMI unit are built on it and on ``wire``, which says how a command's inputs
travel. Each is generated from the machine model (``openmotion.kernel.model``), never from a
list of its own. ``serve`` starts a host with the endpoints chosen (``openmotion serve``).
"""

from openmotion.endpoints.ads import AdsServer
from openmotion.endpoints.host import HostError, HostStatus, MachineHost, Pace, Snapshot
from openmotion.endpoints.kernel_process import ProcessHost, SnapshotBoard
from openmotion.endpoints.serve import ENDPOINTS, EndpointUnavailable, Serving, serve
from openmotion.endpoints.wire import (
    HandleState,
    WireCommand,
    WireError,
    WireInput,
    WireKind,
    coerce,
    default_of,
    handle_state,
    wire_commands,
)

__all__ = ["ENDPOINTS", "AdsServer", "EndpointUnavailable", "HandleState", "HostError",
           "HostStatus", "MachineHost", "Pace", "ProcessHost", "Serving", "Snapshot",
           "SnapshotBoard", "WireCommand", "WireError", "WireInput", "WireKind", "coerce",
           "default_of", "handle_state", "serve", "wire_commands"]
