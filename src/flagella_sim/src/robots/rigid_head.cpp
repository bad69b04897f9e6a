#include "flagella_sim/robots/rigid_head.h"

namespace flagella {

RigidHead addRigidHead(NetworkBuilder& b, double h, const RodMaterial& m, double k) {
  RigidHead head;
  head.x0 = b.addNode(Vec3(0, 0, -h));
  head.x1 = b.addNode(Vec3(0, 0, 0));
  head.x2 = b.addNode(Vec3(0, 0, h));
  head.e0 = b.addEdge(head.x0, head.x1, m, k);
  head.e1 = b.addEdge(head.x1, head.x2, m, k);
  RobotParts& parts = b.parts();
  parts.head_front_node = head.x0;
  parts.head_center_node = head.x1;
  parts.joint_node = head.x2;
  parts.head_edge = head.e0;
  parts.shaft_edge = head.e1;
  parts.head_nodes = {head.x0, head.x1, head.x2};
  parts.motor_spring = b.addBendTwistSpring(head.e0, head.e1, m, k);  // docs/model.md 1.9
  return head;
}

}  // namespace flagella
