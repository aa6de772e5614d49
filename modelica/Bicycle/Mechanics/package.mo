within Bicycle;
package Mechanics "Multibody components in generalized coordinates (Kane's method): connectors, bodies, joints, ground"
  annotation(Documentation(info = "<html>
<p>A small multibody library for systems described by a fixed set of <code>n</code> generalized
coordinates <code>q</code> and speeds <code>u</code> (Kane's method), written for the project's
compiler. Every frame connector carries, besides the frame's orientation <code>R</code> and origin
<code>r</code>, its <em>partial angular velocities</em> <code>Wp</code> and <em>partial velocities</em>
<code>Vp</code> (the columns of <code>w = Wp*u</code>, <code>der(r) = Vp*u</code>) and the acceleration
remainders (<code>der(w) = Wp*der(u) + al0</code>, acceleration of the origin <code>Vp*der(u) + a0</code>).
Joints and translations pass these on; every body adds its generalized mass matrix
<code>m Vp'Vp + Wp' I Wp</code> and its generalized forces <code>Vp'(F - m a0) + Wp'(T - I al0 - w x I w)</code>
as <em>flow</em> variables, so that <code>connect()</code> sums them. The root (<a
href=\"modelica://Bicycle.Mechanics.Ground\">Ground</a>) owns the coordinates, eliminates the
dependent speeds through the rolling constraints of the wheels and writes Kane's equations
<code>Mr*der(ui) = fr</code> for the independent speeds (the elimination and Kane's equations are
written once, in <a href=\"modelica://Bicycle.Mechanics.PartialGround\">PartialGround</a>).</p>
<p>Subpackages: <code>Interfaces</code> (the <code>Frame</code> and <code>ContactRows</code> connectors),
<code>Parts</code> (rigid body, fixed translation), <code>Joints</code> (revolute joints, with a torque
input), <code>Frames</code> (the bicycle's rear frame, steer axis and front frame), <code>Rider</code>
(the rider's upper body on a hip hinge with passive stiffness and damping and a lean-torque input, a
locked hinge, and the 7-speed root of the bicycle with the rider). The wheels are in
<a href=\"modelica://Bicycle.Wheels\">Bicycle.Wheels</a>.</p>
<p>Vectors are resolved in ground axes (Meijaard et al. 2007: x forward, y right, z down; the
ground is the plane z = 0). Vector algebra is written element by element (cross products,
rotation matrices) because the Modelica front end used (pymoca 0.12) has no <code>cross()</code>
and no array literals of variables.</p>
</html>"));
end Mechanics;
