"""The OPC UA endpoint: a served machine's address space, generated from its machine model.

Needs the ``endpoints`` extra (asyncua). docs/endpoints.md "OPC UA" shows how to connect
and drive it; D-260 to D-262 record what the address space follows and why.
"""

from openmotion.endpoints.opcua.security import Access
from openmotion.endpoints.opcua.server import (
    APPLICATION_URI,
    DEFAULT_PORT,
    SECURITY_POLICIES,
    OpcUaServer,
)
from openmotion.endpoints.opcua.space import NAMESPACE_URI

__all__ = ["APPLICATION_URI", "DEFAULT_PORT", "NAMESPACE_URI", "SECURITY_POLICIES", "Access",
           "OpcUaServer"]
