within Bicycle.Mechanics;
package Interfaces "Connectors of the generalized-coordinate multibody components"
  extends Bicycle.Icons.InterfacesPackage;
  annotation(Documentation(info = "<html><p><code>Frame_a</code>, <code>Frame_b</code>: a body-fixed
coordinate system with its kinematics in terms of the generalized speeds (causal, from the ground
outwards) and three acausal pairs: generalized speeds and the speeds the joints own, generalized
accelerations and forces (inertia included), gravity and energy. <code>WheelContact</code>,
<code>GroundContact</code>: the velocity-constraint rows of a rolling contact, from the wheel to the
ground. Every connector is balanced (MLS 9.3.1).</p></html>"));
end Interfaces;
