// fail_closed: no node of the face can be written or called by a role it
// does not name.
//
// node-opcua resolves a node without RolePermissions of its own through
// its namespace's DefaultRolePermissions, and the server nulls those at
// start, which grants every permission (CVE-2026-95860, "namespace-level
// RBAC fail-open"): an anonymous session could call the Server object's
// methods or write any variable whose AccessLevel allows it, the types'
// instance declarations among them. The face's own instances carry their
// permissions; here every other Method and writable Variable gets explicit
// ones: browse and read for everyone, Call for signed-in users only (the
// standard methods a client uses, such as GetMonitoredItems), Write for
// nobody.
"use strict";
const {
  AccessLevelFlag,
  DataType,
  NodeClass,
  PermissionType,
  RolePermissionType,
  VariantArrayType,
  WellKnownRoles,
  resolveNodeId,
  setNamespaceMetaData,
} = require("node-opcua");

const kLook = PermissionType.Browse | PermissionType.Read | PermissionType.ReadRolePermissions;

function closedPermissions(node) {
  const anonymous = resolveNodeId(WellKnownRoles.Anonymous);
  const signedIn = resolveNodeId(WellKnownRoles.AuthenticatedUser);
  if (node.nodeClass === NodeClass.Method) {
    return [
      { roleId: anonymous, permissions: kLook },
      { roleId: signedIn, permissions: kLook | PermissionType.Call },
    ];
  }
  return [
    { roleId: anonymous, permissions: kLook },
    { roleId: signedIn, permissions: kLook },
  ];
}

function isOpen(node) {
  if (node.rolePermissions) return false;
  if (node.nodeClass === NodeClass.Method) return true;
  return node.nodeClass === NodeClass.Variable && (node.accessLevel & AccessLevelFlag.CurrentWrite) !== 0;
}

// What a node the server creates later (a session's diagnostics) falls
// back to: its namespace's DefaultRolePermissions, here browse, read and
// (signed in) call, never write.
function closeNamespaceDefaults(addressSpace) {
  const namespaces = addressSpace.rootFolder.objects.server.getChildByName("Namespaces");
  for (const namespace of addressSpace.getNamespaceArray()) {
    const closed = closedPermissions({ nodeClass: NodeClass.Method }).map((p) => new RolePermissionType(p));
    namespace.setDefaultRolePermissions(closed);
    const metaData = namespaces && namespaces.getChildByName(namespace.namespaceUri);
    if (!metaData) {
      setNamespaceMetaData(namespace);  // bound to the namespace's defaults
      continue;
    }
    for (const name of ["DefaultRolePermissions", "DefaultUserRolePermissions"]) {
      const variable = metaData.getChildByName(name);
      if (variable) {
        variable.setValueFromSource({ dataType: DataType.ExtensionObject, arrayType: VariantArrayType.Array, value: closed });
      }
    }
  }
}

// Gives explicit permissions to every Method and writable Variable of the
// address space that has none, and closes every namespace's defaults;
// returns how many nodes it closed. Call it after server.initialize()
// (which nulls the namespaces' defaults) and before server.start().
function closeUnlistedNodes(addressSpace) {
  let closed = 0;
  for (const namespace of addressSpace.getNamespaceArray()) {
    for (const node of namespace.nodeIterator()) {
      if (!isOpen(node)) continue;
      node.setRolePermissions(closedPermissions(node));
      closed += 1;
    }
  }
  closeNamespaceDefaults(addressSpace);
  return closed;
}

module.exports = { closeUnlistedNodes };
