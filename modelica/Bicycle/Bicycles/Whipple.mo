within Bicycle.Bicycles;
model Whipple "Nonlinear Whipple bicycle (Meijaard et al. 2007): rear wheel, rear frame, steer axis, front frame, front wheel rolling on flat ground"
  extends Bicycle.Mechanics.Ground;
  replaceable package Data = Bicycle.Records.Benchmark constrainedby Bicycle.Records.PartialWhipple "Parameter set (defaults of the parameters below)";
  parameter Bicycle.Units.Length w(min = 1e-6) = Data.w "Wheelbase w";
  parameter Bicycle.Units.Length c = Data.c "Trail c (positive: front contact point behind the steer axis)";
  parameter Bicycle.Units.Angle lam(min = -1.5707963267948966, max = 1.5707963267948966) = Data.lam "Steer-axis tilt lam from the vertical (pi/2 - head angle)";
  parameter Bicycle.Units.Acceleration g(min = 0) = Data.g "Gravitational acceleration g";
  parameter Bicycle.Units.Length rR(min = 1e-6) = Data.rR "Rear wheel radius rR (centre height of the upright wheel)";
  parameter Bicycle.Units.Mass mR(min = 0) = Data.mR "Rear wheel mass mR";
  parameter Bicycle.Units.MomentOfInertia IRxx(min = 0) = Data.IRxx "Rear wheel diametral inertia IRxx = IRzz";
  parameter Bicycle.Units.MomentOfInertia IRyy(min = 0) = Data.IRyy "Rear wheel spin inertia IRyy";
  parameter Bicycle.Units.Position xB = Data.xB "Rear frame centre of mass: x coordinate xB (forward)";
  parameter Bicycle.Units.Position zB(max = 0) = Data.zB "Rear frame centre of mass: z coordinate zB (down; negative above the ground)";
  parameter Bicycle.Units.Mass mB(min = 0) = Data.mB "Rear frame mass mB";
  parameter Bicycle.Units.MomentOfInertia IBxx(min = 0) = Data.IBxx "Rear frame inertia-tensor element IBxx about its centre of mass";
  parameter Bicycle.Units.MomentOfInertia IBxz = Data.IBxz "Rear frame inertia-tensor element IBxz about its centre of mass";
  parameter Bicycle.Units.MomentOfInertia IByy(min = 0) = Data.IByy "Rear frame inertia-tensor element IByy about its centre of mass";
  parameter Bicycle.Units.MomentOfInertia IBzz(min = 0) = Data.IBzz "Rear frame inertia-tensor element IBzz about its centre of mass";
  parameter Bicycle.Units.Position xH = Data.xH "Front frame centre of mass: x coordinate xH (forward)";
  parameter Bicycle.Units.Position zH(max = 0) = Data.zH "Front frame centre of mass: z coordinate zH (down; negative above the ground)";
  parameter Bicycle.Units.Mass mH(min = 0) = Data.mH "Front frame mass mH";
  parameter Bicycle.Units.MomentOfInertia IHxx(min = 0) = Data.IHxx "Front frame inertia-tensor element IHxx about its centre of mass";
  parameter Bicycle.Units.MomentOfInertia IHxz = Data.IHxz "Front frame inertia-tensor element IHxz about its centre of mass";
  parameter Bicycle.Units.MomentOfInertia IHyy(min = 0) = Data.IHyy "Front frame inertia-tensor element IHyy about its centre of mass";
  parameter Bicycle.Units.MomentOfInertia IHzz(min = 0) = Data.IHzz "Front frame inertia-tensor element IHzz about its centre of mass";
  parameter Bicycle.Units.Length rF(min = 1e-6) = Data.rF "Front wheel radius rF (centre height of the upright wheel)";
  parameter Bicycle.Units.Mass mF(min = 0) = Data.mF "Front wheel mass mF";
  parameter Bicycle.Units.MomentOfInertia IFxx(min = 0) = Data.IFxx "Front wheel diametral inertia IFxx = IFzz";
  parameter Bicycle.Units.MomentOfInertia IFyy(min = 0) = Data.IFyy "Front wheel spin inertia IFyy";
  parameter Bicycle.Units.Length tR(min = 0) = 0 "Rear tyre crown radius tR (toroidal wheel; 0: knife edge)";
  parameter Bicycle.Units.Length tF(min = 0) = 0 "Front tyre crown radius tF (toroidal wheel; 0: knife edge)";
  Bicycle.Interfaces.RealInput T_delta(final quantity = "Torque", final unit = "N.m") "Steer torque T_delta between rear frame and front frame, positive tending to steer right";
  replaceable Bicycle.Wheels.Torus rearWheel(t = tR) constrainedby Bicycle.Wheels.PartialWheel(n = n, sel = {0, 0, 1, 0, 0, 0}, r = rR, m = mR, Ixx = IRxx, Iyy = IRyy, g = g) "Rear wheel R (spin angle thetaR)";
  Bicycle.Mechanics.Frames.RearFrame rearFrame(n = n, w = w, c = c, rR = rR, xB = xB, zB = zB, mB = mB, IBxx = IBxx, IBxz = IBxz, IByy = IByy, IBzz = IBzz, g = g) "Rear frame B with the rider";
  Bicycle.Mechanics.Frames.SteerAxis steer(n = n, sel = {0, 1, 0, 0, 0, 0}, lam = lam) "Steer axis (steer angle delta)";
  Bicycle.Mechanics.Frames.FrontFrame frontFrame(n = n, w = w, c = c, rF = rF, xH = xH, zH = zH, mH = mH, IHxx = IHxx, IHxz = IHxz, IHyy = IHyy, IHzz = IHzz, g = g) "Front frame H (fork and handlebar)";
  replaceable Bicycle.Wheels.Torus frontWheel(t = tF) constrainedby Bicycle.Wheels.PartialWheel(n = n, sel = {0, 0, 0, 0, 0, 1}, r = rF, m = mF, Ixx = IFxx, Iyy = IFyy, g = g) "Front wheel F (spin angle thetaF)";
equation
  connect(rear, rearWheel.hub);
  connect(rear, rearFrame.frame_a);
  connect(rearWheel.contact, rearContact);
  connect(rearFrame.frame_b, steer.frame_a);
  connect(steer.frame_b, frontFrame.frame_a);
  connect(frontFrame.frame_b, frontWheel.hub);
  connect(frontWheel.contact, frontContact);
  connect(T_delta, steer.tau_in);
  annotation(
    experiment(StartTime = 0, StopTime = 10, Tolerance = 1e-10, Interval = 0.01),
    __Cosim(export = true,
      singular(
        delta(angle_deg = 90, tolerance_deg = 15, description = "the front wheel stands across the rear frame, where the rolling constraints of the two wheels lose rank (near +-90 deg: the exact steer angle moves with lean and pitch)"),
        phi(angle_deg = 90, tolerance_deg = 15, description = "the wheels lie flat on the ground, where their contact points are undefined"))),
    Documentation(info = "<html>
<p>The nonlinear Whipple bicycle assembled from components: rear wheel R, rear frame B (rider
rigidly attached), steer axis, front frame H (fork and handlebar), front wheel F, with the
parameters of Meijaard et al. (2007), Table 1 (defaults: the data set <code>Data</code>) and toroidal
wheels with crown radii <code>tR</code>, <code>tF</code> (0: knife edge). Rolling without slip on flat
ground; the equations of motion are Kane's, assembled by <a href=\"modelica://Bicycle.Mechanics.Ground\">Ground</a>
(which this model extends: it owns the coordinates and the independent speeds) from the bodies'
contributions.</p>
<p>States: rear contact point <code>x, y</code>; yaw <code>psi</code>, roll <code>phi</code>, pitch
<code>theta</code>, steer <code>delta</code>, wheel angles <code>thetaR, thetaF</code>; the independent
speeds <code>u_phi, u_delta, u_R</code>. The dependent speeds <code>u_psi, u_theta, u_F</code> and their
rates are outputs, with the forward speed <code>v</code>, the total energy <code>E</code> and the
holonomic constraint residual (height of the front contact point). Inputs: the steer torque
<code>T_delta</code> and a roll torque <code>T_phi</code> on the rear frame.</p>
<p>Signs are Meijaard's: x forward, y right, z down; roll positive leaning right, steer positive to
the right, yaw positive turning right, pitch positive nose up; wheel rates are negative when rolling
forward (forward speed <code>v = -u_R rR</code> upright).</p>
<p>The wheels are replaceable components constrained by <code>Bicycle.Wheels.PartialWheel</code>
(whose modifiers, given in the constraining clause, apply to every replacement), e.g.
<code>extends Whipple(redeclare Bicycle.Wheels.CrownedRoller rearWheel(R = 0.4))</code> or
<code>redeclare Bicycle.Wheels.KnifeEdge frontWheel</code>. The equations equal those of the flat model
generated by sympy (<code>tests/oracle</code>, <code>tests/test_component_bicycle.py</code>).</p>
</html>"));
end Whipple;
