within Bicycle.Bicycles;
model WhippleLinear "Linearized Whipple bicycle, eq (24): M q'' + v C1 q' + (g K0 + v^2 K2) q = [T_phi, T_delta] (Meijaard et al. 2007)"
  // Geometry and gravity (Meijaard et al. 2007, Table 1; defaults: the benchmark bicycle)
  parameter Bicycle.Units.Length w(min = 1e-6) = 1.02 "Wheelbase w";
  parameter Bicycle.Units.Length c = 0.08 "Trail c (positive: front contact point behind the steer axis)";
  parameter Bicycle.Units.Angle lam(min = -1.5707963267948966, max = 1.5707963267948966) = 0.3141592653589793 "Steer-axis tilt lam from the vertical (pi/2 - head angle), in (-pi/2, pi/2)";
  parameter Bicycle.Units.Acceleration g(min = 0) = 9.81 "Gravitational acceleration g";
  // Rear wheel R
  parameter Bicycle.Units.Length rR(min = 1e-6) = 0.3 "Rear wheel radius rR";
  parameter Bicycle.Units.Mass mR(min = 0) = 2 "Rear wheel mass mR";
  parameter Bicycle.Units.MomentOfInertia IRxx(min = 0) = 0.0603 "Rear wheel diametral inertia IRxx = IRzz";
  parameter Bicycle.Units.MomentOfInertia IRyy(min = 0) = 0.12 "Rear wheel spin inertia IRyy";
  // Rear frame B with rider
  parameter Bicycle.Units.Position xB = 0.3 "Rear frame centre of mass: x coordinate xB (forward)";
  parameter Bicycle.Units.Position zB(max = 0) = -0.9 "Rear frame centre of mass: z coordinate zB (down; negative above the ground)";
  parameter Bicycle.Units.Mass mB(min = 0) = 85 "Rear frame (with rider) mass mB";
  parameter Bicycle.Units.MomentOfInertia IBxx(min = 0) = 9.2 "Rear frame inertia-tensor element IBxx about its centre of mass";
  parameter Bicycle.Units.MomentOfInertia IBxz = 2.4 "Rear frame inertia-tensor element IBxz about its centre of mass";
  parameter Bicycle.Units.MomentOfInertia IByy(min = 0) = 11 "Rear frame inertia-tensor element IByy about its centre of mass (does not enter the linear model)";
  parameter Bicycle.Units.MomentOfInertia IBzz(min = 0) = 2.8 "Rear frame inertia-tensor element IBzz about its centre of mass";
  // Front frame H (fork and handlebar)
  parameter Bicycle.Units.Position xH = 0.9 "Front frame centre of mass: x coordinate xH (forward)";
  parameter Bicycle.Units.Position zH(max = 0) = -0.7 "Front frame centre of mass: z coordinate zH (down; negative above the ground)";
  parameter Bicycle.Units.Mass mH(min = 0) = 4 "Front frame mass mH";
  parameter Bicycle.Units.MomentOfInertia IHxx(min = 0) = 0.05892 "Front frame inertia-tensor element IHxx about its centre of mass";
  parameter Bicycle.Units.MomentOfInertia IHxz = -0.00756 "Front frame inertia-tensor element IHxz about its centre of mass";
  parameter Bicycle.Units.MomentOfInertia IHyy(min = 0) = 0.06 "Front frame inertia-tensor element IHyy about its centre of mass (does not enter the linear model)";
  parameter Bicycle.Units.MomentOfInertia IHzz(min = 0) = 0.00708 "Front frame inertia-tensor element IHzz about its centre of mass";
  // Front wheel F
  parameter Bicycle.Units.Length rF(min = 1e-6) = 0.35 "Front wheel radius rF";
  parameter Bicycle.Units.Mass mF(min = 0) = 3 "Front wheel mass mF";
  parameter Bicycle.Units.MomentOfInertia IFxx(min = 0) = 0.1405 "Front wheel diametral inertia IFxx = IFzz";
  parameter Bicycle.Units.MomentOfInertia IFyy(min = 0) = 0.28 "Front wheel spin inertia IFyy";
  // Operating point and initial state
  parameter Bicycle.Units.Velocity v = 5 "Forward speed v of the rear contact point (negative: riding backwards, i.e. a rear-steered bicycle)";
  parameter Bicycle.Units.Angle phi0 = 0 "Initial roll angle";
  parameter Bicycle.Units.Angle delta0 = 0 "Initial steer angle";
  parameter Bicycle.Units.AngularVelocity phi_dot0 = 0 "Initial roll rate";
  parameter Bicycle.Units.AngularVelocity delta_dot0 = 0 "Initial steer rate";

  Bicycle.Bodies.RearWheel rearWheel(r = rR, m = mR, Ixx = IRxx, Iyy = IRyy) "Rear wheel R";
  Bicycle.Bodies.RearFrame rearFrame(x = xB, z = zB, m = mB, Ixx = IBxx, Ixz = IBxz, Iyy = IByy, Izz = IBzz) "Rear frame B with rider";
  Bicycle.Bodies.FrontFrame frontFrame(x = xH, z = zH, m = mH, Ixx = IHxx, Ixz = IHxz, Iyy = IHyy, Izz = IHzz) "Front frame H (fork and handlebar)";
  Bicycle.Bodies.FrontWheel frontWheel(w = w, r = rF, m = mF, Ixx = IFxx, Iyy = IFyy) "Front wheel F";

  // Whole bicycle T (Meijaard 2007, eqs A1-A6): sums of the bodies' moments about the rear contact point
  // (the rear wheel centre lies above the origin: it adds nothing to m*x and Jxz)
  final parameter Bicycle.Units.Mass mT = rearWheel.m + rearFrame.m + frontFrame.m + frontWheel.m "Total mass mT (A1)";
  final parameter Bicycle.Units.Position xT = (rearFrame.mx + frontFrame.mx + frontWheel.mx)/mT "Total centre of mass: x coordinate xT (A2)";
  final parameter Bicycle.Units.Position zT = (rearWheel.mz + rearFrame.mz + frontFrame.mz + frontWheel.mz)/mT "Total centre of mass: z coordinate zT (A2)";
  final parameter Bicycle.Units.MomentOfInertia ITxx = rearWheel.Jxx + rearFrame.Jxx + frontFrame.Jxx + frontWheel.Jxx "Total inertia ITxx about the rear contact point (A3)";
  final parameter Bicycle.Units.MomentOfInertia ITxz = rearFrame.Jxz + frontFrame.Jxz + frontWheel.Jxz "Total inertia-tensor element ITxz about the rear contact point (A4)";
  final parameter Bicycle.Units.MomentOfInertia ITzz = rearWheel.Jzz + rearFrame.Jzz + frontFrame.Jzz + frontWheel.Jzz "Total inertia ITzz about the rear contact point (A6)";
  // Front assembly A = H + F (A7-A12): inertia about its own centre of mass by the parallel-axis theorem
  final parameter Bicycle.Units.Mass mA = frontFrame.m + frontWheel.m "Front assembly mass mA (A7)";
  final parameter Bicycle.Units.Position xA = (frontFrame.mx + frontWheel.mx)/mA "Front assembly centre of mass: x coordinate xA (A8)";
  final parameter Bicycle.Units.Position zA = (frontFrame.mz + frontWheel.mz)/mA "Front assembly centre of mass: z coordinate zA (A8)";
  final parameter Bicycle.Units.MomentOfInertia IAxx = frontFrame.Jxx + frontWheel.Jxx - mA*zA^2 "Front assembly inertia IAxx about its centre of mass (A9)";
  final parameter Bicycle.Units.MomentOfInertia IAxz = frontFrame.Jxz + frontWheel.Jxz + mA*xA*zA "Front assembly inertia-tensor element IAxz about its centre of mass (A10)";
  final parameter Bicycle.Units.MomentOfInertia IAzz = frontFrame.Jzz + frontWheel.Jzz - mA*xA^2 "Front assembly inertia IAzz about its centre of mass (A11)";
  // Steer axis: unit vector (sin(lam), 0, cos(lam)) through the point (w + c, 0, 0)
  final parameter Bicycle.Units.Position uA = (xA - w - c)*cos(lam) - zA*sin(lam) "Distance uA of the front assembly centre of mass from the steer axis (A12; positive in front)";
  final parameter Bicycle.Units.MomentOfInertia IAll = mA*uA^2 + IAxx*sin(lam)^2 + 2*IAxz*sin(lam)*cos(lam) + IAzz*cos(lam)^2 "Front assembly inertia IAll about the steer axis (A13)";
  final parameter Bicycle.Units.MomentOfInertia IAlx = -mA*uA*zA + IAxx*sin(lam) + IAxz*cos(lam) "Front assembly inertia product IAlx of the steer axis and the x axis through the rear contact point (A14)";
  final parameter Bicycle.Units.MomentOfInertia IAlz = mA*uA*xA + IAxz*sin(lam) + IAzz*cos(lam) "Front assembly inertia product IAlz of the steer axis and the z axis through the rear contact point (A15)";
  final parameter Bicycle.Units.DimensionlessRatio mu = c/w*cos(lam) "Trail factor mu = c cos(lam)/w (A16)";
  final parameter Bicycle.Units.FirstMomentOfMass SR = rearWheel.S "Rear wheel gyrostatic coefficient SR = IRyy/rR (A17)";
  final parameter Bicycle.Units.FirstMomentOfMass SF = frontWheel.S "Front wheel gyrostatic coefficient SF = IFyy/rF (A17)";
  final parameter Bicycle.Units.FirstMomentOfMass ST = SR + SF "Total gyrostatic coefficient ST = SR + SF (A18)";
  final parameter Bicycle.Units.FirstMomentOfMass SA = mA*uA + mu*mT*xT "Static moment SA of the steer axis (A19)";
  // Mass matrix M (A20)
  final parameter Bicycle.Units.MomentOfInertia M11 = ITxx "Mass matrix M, element (phi, phi)";
  final parameter Bicycle.Units.MomentOfInertia M12 = IAlx + mu*ITxz "Mass matrix M, element (phi, delta)";
  final parameter Bicycle.Units.MomentOfInertia M21 = M12 "Mass matrix M, element (delta, phi) = M12";
  final parameter Bicycle.Units.MomentOfInertia M22 = IAll + 2*mu*IAlz + mu^2*ITzz "Mass matrix M, element (delta, delta)";
  // Gravity stiffness K0 (A21), multiplied by g
  final parameter Bicycle.Units.FirstMomentOfMass K0_11 = mT*zT "Gravity stiffness K0, element (phi, phi)";
  final parameter Bicycle.Units.FirstMomentOfMass K0_12 = -SA "Gravity stiffness K0, element (phi, delta)";
  final parameter Bicycle.Units.FirstMomentOfMass K0_21 = -SA "Gravity stiffness K0, element (delta, phi) = K0_12";
  final parameter Bicycle.Units.FirstMomentOfMass K0_22 = -SA*sin(lam) "Gravity stiffness K0, element (delta, delta)";
  // Velocity-squared stiffness K2 (A22), multiplied by v^2; K2_11 = K2_21 = 0
  final parameter Bicycle.Units.MassCoefficient K2_12 = (ST - mT*zT)*cos(lam)/w "Velocity-squared stiffness K2, element (phi, delta); K2_11 = K2_21 = 0";
  final parameter Bicycle.Units.MassCoefficient K2_22 = (SA + SF*sin(lam))*cos(lam)/w "Velocity-squared stiffness K2, element (delta, delta)";
  // Velocity-proportional matrix C1 (A23-A26), multiplied by v; C1_11 = 0
  final parameter Bicycle.Units.FirstMomentOfMass C1_12 = mu*ST + SF*cos(lam) + ITxz*cos(lam)/w - mu*mT*zT "Velocity-proportional matrix C1, element (phi, delta); C1_11 = 0";
  final parameter Bicycle.Units.FirstMomentOfMass C1_21 = -(mu*ST + SF*cos(lam)) "Velocity-proportional matrix C1, element (delta, phi)";
  final parameter Bicycle.Units.FirstMomentOfMass C1_22 = IAlz*cos(lam)/w + mu*(SA + ITzz*cos(lam)/w) "Velocity-proportional matrix C1, element (delta, delta)";

  input Bicycle.Units.Torque T_phi "Roll torque T_phi on the rear frame, positive tending to lean right";
  input Bicycle.Units.Torque T_delta "Steer torque T_delta between rear frame and front frame, positive tending to steer right";
  output Bicycle.Units.Angle phi(start = phi0, fixed = true) "Roll angle phi of the rear frame, positive leaning right";
  output Bicycle.Units.Angle delta(start = delta0, fixed = true) "Steer angle delta, positive steering right";
  output Bicycle.Units.AngularVelocity phi_dot(start = phi_dot0, fixed = true) "Roll rate der(phi)";
  output Bicycle.Units.AngularVelocity delta_dot(start = delta_dot0, fixed = true) "Steer rate der(delta)";
  output Bicycle.Units.Angle psi(start = 0, fixed = true) "Yaw (heading) angle psi of the rear frame, positive turning right (about the downward z axis)";
  output Bicycle.Units.Position y(start = 0, fixed = true) "Lateral position y of the rear contact point, positive to the right of the initial path";
equation
  der(phi) = phi_dot;
  der(delta) = delta_dot;
  // Linear in the accelerations: the compiler solves the 2x2 mass-matrix system for der(phi_dot), der(delta_dot).
  M11*der(phi_dot) + M12*der(delta_dot) + v*C1_12*delta_dot + g*K0_11*phi + (g*K0_12 + v^2*K2_12)*delta = T_phi;
  M21*der(phi_dot) + M22*der(delta_dot) + v*(C1_21*phi_dot + C1_22*delta_dot) + g*K0_21*phi + (g*K0_22 + v^2*K2_22)*delta = T_delta;
  // Heading and path of the rear contact point, linearized about straight running
  der(psi) = (v*delta + c*delta_dot)*cos(lam)/w;
  der(y) = v*psi;
  annotation(
    experiment(StartTime = 0, StopTime = 5, Tolerance = 1e-8, Interval = 0.01),
    __Cosim(export = true),
    Documentation(info = "<html>
<p>The linearized Whipple bicycle of J. P. Meijaard, J. M. Papadopoulos, A. Ruina and A. L. Schwab,
<em>Linearized dynamics equations for the balance and steer of a bicycle: a benchmark and review</em>,
Proc. R. Soc. A 463 (2007) 1955-1982, which is eq (24) of Astrom, Klein and Lennartsson (2005):</p>
<pre>  M q'' + v C1 q' + (g K0 + v^2 K2) q = [T_phi; T_delta],   q = [phi; delta]</pre>
<p>M, C1, K0 and K2 are calculated parameters computed from the four rigid bodies of
<code>Bicycle.Bodies</code> following Meijaard's Appendix A: the bodies' first moments and
inertias about the rear contact point are summed to the whole bicycle, the front assembly's
inertia about its own centre of mass follows by the parallel-axis theorem. The top-level
parameters carry the names of Meijaard's Table 1; their defaults are the benchmark bicycle,
for which M, C1, K0, K2 equal the published 14-digit values and the bicycle is self-stable for
4.292 m/s &lt; v &lt; 6.024 m/s. Structural zeros C1_11 = K2_11 = K2_21 = 0 are not declared.</p>
<p><b>Sign conventions are those of Meijaard (2007)</b>, not the ISO 8855 conventions of the
rest of this library: axes x forward, y right, z down; roll phi positive leaning right, steer
delta and steer torque T_delta positive steering right (Astrom et al. 2005 count the steer
angle positive to the left: their matrices are S M S etc. with S = diag(1, -1)), yaw psi
positive turning right, lateral position y of the rear contact point positive to the right.
The heading and path kinematics, linearized about straight running at speed v, are
(Meijaard 2007, section 3):</p>
<pre>  der(psi) = (v delta + c der(delta)) cos(lam)/w,   der(y) = v psi</pre>
<p>psi and y do not feed back into the dynamics: the continuous states are, in this order,
phi, delta, phi_dot, delta_dot, psi, y, and the upper-left 4x4 block of the state matrix is the
Whipple model's (its eigenvalues are the bicycle's; psi and y add two eigenvalues at zero).
A negative speed v is riding backwards, i.e. a rear-steered bicycle.</p>
</html>"));
end WhippleLinear;
