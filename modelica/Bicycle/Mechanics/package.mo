within Bicycle;
package Mechanics "Multibody components in generalized coordinates (Kane's method): connectors, bodies, joints, ground"
  extends Bicycle.Icons.Package;
  annotation(Documentation(info = "<html>
<p>A small multibody library for systems described by <code>n</code> generalized speeds
<code>u</code> (Kane's method). Every frame connector carries, besides the frame's orientation
<code>R</code> and origin <code>r</code>, its <em>partial angular velocities</em> <code>Wp</code> and
<em>partial velocities</em> <code>Vp</code> (the columns of <code>w = Wp*u</code>, <code>der(r) =
Vp*u</code>) and the acceleration remainders (<code>der(w) = Wp*du + al0</code>, acceleration of the
origin <code>Vp*du + a0</code>), all causal from the ground outwards. Joints pass these on and add the
column of their own coordinate; every body adds its generalized active and inertia forces
<code>Vp'(F - m a) + Wp'(T - I al - w x I w)</code>, written with the generalized accelerations
<code>du</code>, as a <em>flow</em>, so that <code>connect()</code> sums them. The ground (<a
href=\"modelica://Bicycle.Mechanics.Ground\">Ground</a>), a component, eliminates the dependent speeds
through the rolling constraints of the wheels and states Kane's equations for the independent ones.</p>
<p>Subpackages: <code>Interfaces</code> (the frame and contact connectors, all balanced),
<code>Parts</code> (rigid body, fixed translation), <code>Joints</code> (revolute joints that own their
coordinate: free, driven by a torque with a spring and damper, held), <code>Frames</code> (the
bicycle's rear frame, steer axis and front frame), <code>Rider</code> (the rider's upper body on a hip
hinge: free with stiffness, damping and a lean torque; locked; lean and twist). The wheels are in
<a href=\"modelica://Bicycle.Wheels\">Bicycle.Wheels</a>.</p>
<p>Vectors are resolved in ground axes (Meijaard et al. 2007: x forward, y right, z down; the
ground is the plane z = 0). Vector algebra is written element by element (cross products,
rotation matrices) because the Modelica front end used (pymoca 0.12) has no <code>cross()</code>
and no array literals of variables.</p>
</html>"));
end Mechanics;
