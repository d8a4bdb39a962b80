"""Who may do what on the OPC UA server: users, roles, the rules per request, certificates.

Anonymous sessions read, browse and subscribe; only a user may call a method or write
(D-262). A user is a name with a password (``--user NAME:PASSWORD`` or a users file) or a
client certificate the server was told to trust (of the identity token, or of the secure
channel). A server started ``writable`` with no users
lets anonymous sessions command too: a test harness on loopback needs no credentials.
"""

from __future__ import annotations

import hmac
from collections.abc import Iterable, Mapping
from typing import Any

from asyncua import ua
from asyncua.crypto.permission_rules import USER_TYPES, PermissionRuleset, User, UserRole

from openmotion.core.errors import ConfigError

__all__ = ["Access"]

#: the requests that change the machine: only a user's session may send them
COMMANDING = frozenset(ua.NodeId(kind) for kind in (
    ua.ObjectIds.WriteRequest_Encoding_DefaultBinary,
    ua.ObjectIds.CallRequest_Encoding_DefaultBinary))
_ALL = frozenset(ua.NodeId(kind) for kind in USER_TYPES)
_READING = _ALL - COMMANDING


class Access(PermissionRuleset):
    """The users of one server and what each session may send (asyncua's user manager and
    permission ruleset in one)."""

    def __init__(self, users: Mapping[str, str] | None = None,
                 certificates: Iterable[bytes] = (), *, writable: bool = False) -> None:
        self.users = dict(users or {})
        self.certificates = {bytes(der): f"certificate {i + 1}"
                             for i, der in enumerate(certificates)}
        if writable and (self.users or self.certificates):
            raise ConfigError("a writable server lets anonymous clients command; with users "
                              "configured only they may: choose one")
        self.writable = writable

    @property
    def tokens(self) -> list[type]:
        """The identity tokens the endpoints offer."""
        tokens: list[type] = [ua.AnonymousIdentityToken]
        if self.users:
            tokens.append(ua.UserNameIdentityToken)
        if self.certificates:
            tokens.append(ua.X509IdentityToken)
        return tokens

    def get_user(self, iserver: Any, username: str | None = None, password: str | None = None,
                 certificate: Any = None) -> User | None:
        """The session's user, or None to refuse the session (BadUserAccessDenied)."""
        if username is not None:
            expected = self.users.get(username)
            given = password if isinstance(password, str) else \
                bytes(password or b"").decode("utf-8", "replace")
            if expected is None or not hmac.compare_digest(expected.encode(), given.encode()):
                return None
            return User(role=UserRole.User, name=username)
        # the certificate of the identity token or, for any other token, of the secure
        # channel: a trusted one makes a user, any other leaves the session anonymous
        name = self.certificates.get(bytes(certificate)) if certificate else None
        if name is not None:
            return User(role=UserRole.User, name=name)
        return User(role=UserRole.User if self.writable else UserRole.Anonymous)

    def check_validity(self, user: User, action_type_id: ua.NodeId, body: Any) -> bool:
        allowed = _ALL if user is not None and user.role in (UserRole.User, UserRole.Admin) \
            else _READING
        return action_type_id in allowed
