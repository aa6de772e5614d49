within Bicycle.Bodies;
model FrontWheel "Front wheel F: axisymmetric knife-edge wheel with its centre one wheelbase ahead (Meijaard 2007, Table 1)"
  extends Bicycle.Bodies.Wheel(r = 0.35, m = 3, Ixx = 0.1405, Iyy = 0.28);
  parameter Bicycle.Units.Length w(min = 1e-6) = 1.02 "Wheelbase w (x coordinate of the front wheel centre)";
  final parameter Bicycle.Units.FirstMomentOfMass mx = m*w "First moment of mass m*x about the rear contact point";
  final parameter Bicycle.Units.MomentOfInertia Jxz = m*w*r "Inertia-tensor element xz about the rear contact point (parallel axes: -m*x*z)";
  final parameter Bicycle.Units.MomentOfInertia Jzz = Ixx + m*w^2 "Inertia-tensor element zz about the rear contact point (parallel axes)";
  annotation(Documentation(info = "<html>
<p>Front wheel with its centre at x = w, z = -r, straight above the front contact point of the
upright bicycle with zero steer. Defaults: the benchmark bicycle of Meijaard et al. (2007)
(rF, mF, IFxx, IFyy).</p>
</html>"));
end FrontWheel;
