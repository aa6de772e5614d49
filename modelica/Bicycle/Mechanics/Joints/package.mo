within Bicycle.Mechanics;
package Joints "Joints between frames"
  extends Bicycle.Icons.Package;
  annotation(Documentation(info = "<html><p>Revolute joints that own their coordinate: the angle and
its rate are states of the joint, and the joint's column <code>k</code> among the generalized speeds
is its only tie to the rest of the system.</p></html>"));
end Joints;
