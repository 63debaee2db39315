% Williams-2015 scenario: García-Fernández's PMBM filter (the PMBM paper's MATLAB code, run as a peer under
% GNU Octave) on scans exported by hypotrack. hypotrack.experiments.williams2015.reference writes the
% prelude that sets the variables below, then runs this file; nothing here draws a random number.
%
% Set by the prelude:
%   pmbm_dir, assign_dir, tcl_dir   folders of the reference's PMBM filter, its Assignment code and the NRL
%                                    Tracker Component Library's k-best helpers (added to the path)
%   scans_file     CSV "run,scan,x,y" (one row per return; scans without returns have none)
%   runs_file      CSV "run" (the runs to filter, one per line)
%   out_file       CSV written here: "run,scan,label,x,y" (one row per estimated object; label: the Bernoulli
%                  component's tag [t_ini; first association] of the reference's trajectory estimator
%                  PoissonMBMtarget_estimate1_tracks.m, as t_ini * 1e6 + first association)
%   time_file      CSV written here: "run,scan,cpu_s" (CPU time of the update, estimate, pruning, prediction)
%   n_steps, side, clutter_rate, p_d, p_s, q, sigma_r, birth_weight, birth_mean, birth_cov, lambda0
%   (scenario; birth_mean and birth_cov in the reference's [x, vx, y, vy] order)
% The filter settings are those of the reference's demo (PMBMtarget_filter.m, estimator 1).
pkg load statistics
addpath(pmbm_dir); addpath(assign_dir); addpath(tcl_dir);

T = 1;
F = kron(eye(2), [1 T; 0 1]);
Q = q * kron(eye(2), [T^3/3 T^2/2; T^2/2 T]);
H = kron(eye(2), [1 0]);
R = sigma_r^2 * eye(2);
intensity_clutter = clutter_rate / (side * side);
T_pruning = 0.0001; T_pruningPois = 1e-5; Nhyp_max = 200; gating_threshold = 20;
existence_threshold = 0.00001; existence_estimation_threshold1 = 0.4;

S = dlmread(scans_file, ',', 1, 0);
if isempty(S)
  S = zeros(0, 4);
end
runs = dlmread(runs_file, ',', 1, 0);
fo = fopen(out_file, 'w'); fprintf(fo, 'run,scan,label,x,y\n');
ft = fopen(time_file, 'w'); fprintf(ft, 'run,scan,cpu_s\n');
for r = runs(:)'
  filter_pred.weightPois = lambda0;
  filter_pred.meanPois = birth_mean(:);
  filter_pred.covPois = birth_cov;
  filter_pred.tracks = cell(0, 1);
  filter_pred.globHyp = [];
  filter_pred.globHypWeight = [];
  for k = 1:n_steps
    rows = S(:, 1) == r & S(:, 2) == k;
    z = S(rows, 3:4)';
    t0 = cputime;
    filter_upd = PoissonMBMtarget_update(filter_pred, z, H, R, p_d, k, gating_threshold, intensity_clutter, Nhyp_max);
    X_estimate = PoissonMBMtarget_estimate1(filter_upd, existence_estimation_threshold1);
    % the tags of the same components, in the same order (estimate1's selection: the heaviest global
    % hypothesis, existence above the threshold)
    tags = [];
    if ~isempty(filter_upd.globHyp)
      [~, best] = max(filter_upd.globHypWeight);
      for i = 1:columns(filter_upd.globHyp)
        h = filter_upd.globHyp(best, i);
        if h > 0 && filter_upd.tracks{i}.eB(h) > existence_estimation_threshold1
          tags(end + 1) = filter_upd.tracks{i}.t_ini * 1e6 + filter_upd.tracks{i}.aHis{1}(1);
        end
      end
    end
    filter_upd = PoissonMBMtarget_pruning(filter_upd, T_pruning, T_pruningPois, Nhyp_max, existence_threshold);
    filter_pred = PoissonMBMtarget_pred(filter_upd, F, Q, p_s, birth_weight, birth_mean(:), birth_cov);
    fprintf(ft, '%d,%d,%.6f\n', r, k, cputime - t0);
    X = reshape(X_estimate, 4, []);
    if numel(tags) ~= columns(X)
      error('williams2015 reference: %d tags for %d estimates at run %d, step %d', numel(tags), columns(X), r, k);
    end
    for j = 1:columns(X)
      fprintf(fo, '%d,%d,%d,%.10g,%.10g\n', r, k, tags(j), X(1, j), X(3, j));
    end
  end
  fflush(fo); fflush(ft);
  printf('williams2015 reference: run %d done\n', r); fflush(stdout);
end
fclose(fo); fclose(ft);
